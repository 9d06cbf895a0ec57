// Fences for readbacks that must never wait: whether a GL sync object has signaled, asked with a zero
// timeout. FeedbackBuffer and OcclusionQueries read back through persistently mapped buffers fenced this
// way; tests substitute a FenceProbe that holds answers back.
//
// Render thread only, with the GlContext current.
#pragma once

#include <memory>

struct __GLsync;  // GL's sync object (GLsync is a pointer to it); keeps GL headers out of this header

namespace ropecast {

using GlSync = __GLsync*;

// Whether a fence has signaled, asked without waiting.
class FenceProbe {
 public:
  virtual ~FenceProbe() = default;
  virtual bool signaled(GlSync fence) = 0;
};

// Asks GL: glClientWaitSync with timeout 0 and no flush bit (the fence's owner flushed after creating it).
std::unique_ptr<FenceProbe> makeGlFenceProbe();

}  // namespace ropecast
