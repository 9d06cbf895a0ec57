// The table of embedded shader files that the build generates (shaders/embed_shaders.cmake); read through
// shaders/shader_source.h. Immutable; any thread.
#pragma once

#include <cstddef>

namespace ropecast {

struct EmbeddedShaderFile {
  const char* name;  // root-relative path
  const char* text;
};

extern const EmbeddedShaderFile kEmbeddedShaderFiles[];
extern const size_t kEmbeddedShaderFileCount;

}  // namespace ropecast
