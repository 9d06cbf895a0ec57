#include "render/gl_fence.h"

#include <epoxy/gl.h>

#include "core/error.h"

namespace ropecast {

namespace {

class GlFenceProbe final : public FenceProbe {
 public:
  bool signaled(GlSync fence) override {
    const GLenum status = glClientWaitSync(fence, 0, 0);
    if (status == GL_WAIT_FAILED) throw Error("glClientWaitSync failed on a readback fence");
    return status == GL_ALREADY_SIGNALED || status == GL_CONDITION_SATISFIED;
  }
};

}  // namespace

std::unique_ptr<FenceProbe> makeGlFenceProbe() {
  return std::make_unique<GlFenceProbe>();
}

}  // namespace ropecast
