#include "render/index_texture.h"

#include <algorithm>
#include <string>

#include <epoxy/gl.h>

#include "core/error.h"

namespace ropecast {

IndexTexture::IndexTexture(uint32_t componentsPerTexel, int maxTextureBufferTexels)
    : components_(componentsPerTexel), maxTexels_(maxTextureBufferTexels) {
  if (components_ != 1 && components_ != 2 && components_ != 4)
    throw Error("IndexTexture: texels have 1, 2 or 4 components, got " + std::to_string(components_));
  glCreateTextures(GL_TEXTURE_BUFFER, 1, &texture_);
}

IndexTexture::~IndexTexture() {
  if (texture_) glDeleteTextures(1, &texture_);
  if (buffer_) glDeleteBuffers(1, &buffer_);
}

void IndexTexture::upload(std::span<const uint32_t> words) {
  if (words.size() % components_ != 0)
    throw Error("IndexTexture::upload: " + std::to_string(words.size()) + " words is not a whole number of " +
                std::to_string(components_) + "-component texels");
  const size_t texels = words.size() / components_;
  if (maxTexels_ > 0 && texels > size_t(maxTexels_))
    throw Error("IndexTexture::upload: " + std::to_string(texels) +
                " texels exceed GL_MAX_TEXTURE_BUFFER_SIZE " + std::to_string(maxTexels_));
  const size_t bytes = std::max<size_t>(words.size_bytes(), 16);
  if (bytes > capacityBytes_) {
    // A buffer's storage is immutable once attached; grow by making a new, larger one.
    size_t capacity = std::max<size_t>(capacityBytes_, 4096);
    while (capacity < bytes) capacity *= 2;
    if (buffer_) glDeleteBuffers(1, &buffer_);
    glCreateBuffers(1, &buffer_);
    glNamedBufferStorage(buffer_, GLsizeiptr(capacity), nullptr, GL_DYNAMIC_STORAGE_BIT);
    capacityBytes_ = capacity;
  }
  if (!words.empty()) glNamedBufferSubData(buffer_, 0, GLsizeiptr(words.size_bytes()), words.data());
  glTextureBuffer(texture_,
                  components_ == 4   ? GL_RGBA32UI
                  : components_ == 2 ? GL_RG32UI
                                     : GL_R32UI,
                  buffer_);
  texels_ = texels;
}

void IndexTexture::bind(uint32_t unit) const {
  glBindTextureUnit(unit, texture_);
}

}  // namespace ropecast
