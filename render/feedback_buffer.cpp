#include "render/feedback_buffer.h"

#include <algorithm>
#include <string>

#include <epoxy/gl.h>

#include "core/error.h"
#include "render/gl_context.h"

namespace ropecast {

FeedbackBuffer::FeedbackBuffer(const FeedbackBufferConfig& config, std::unique_ptr<FenceProbe> probe)
    : config_(config), probe_(probe ? std::move(probe) : makeGlFenceProbe()) {
  if (config.usedCapacity == 0 || config.requestedCapacity == 0 || config.hitCapacity == 0)
    throw Error("FeedbackBuffer: list capacities must be positive");
  if (config.ringSize == 0) throw Error("FeedbackBuffer: the readback ring needs at least one slot");
  const GLsizeiptr slotBytes = GLsizeiptr(kFeedbackHeaderWords + uint64_t(config.usedCapacity) +
                                          config.requestedCapacity + config.hitCapacity) *
                               4;
  const GLbitfield flags = GL_MAP_READ_BIT | GL_MAP_PERSISTENT_BIT | GL_MAP_COHERENT_BIT;
  ring_.resize(config.ringSize);
  for (Slot& s : ring_) {
    glCreateBuffers(1, &s.buffer);
    glNamedBufferStorage(s.buffer, slotBytes, nullptr, flags);
    s.mapped = static_cast<const uint32_t*>(glMapNamedBufferRange(s.buffer, 0, slotBytes, flags));
    if (!s.mapped) throw Error("FeedbackBuffer: could not map a readback buffer persistently");
  }
  checkGlError("FeedbackBuffer");
}

FeedbackBuffer::~FeedbackBuffer() {
  for (Slot& s : ring_) {
    if (s.fence) glDeleteSync(s.fence);
    if (s.mapped) glUnmapNamedBuffer(s.buffer);
    glDeleteBuffers(1, &s.buffer);
  }
  glDeleteBuffers(1, &storage_);
}

void FeedbackBuffer::begin(uint32_t leafCount, uint32_t hitThreshold) {
  if (inFrame_) throw Error("FeedbackBuffer::begin: the previous frame has not ended");
  words_ = {feedbackMaskWords(leafCount), config_.usedCapacity, config_.requestedCapacity,
            config_.hitCapacity};
  if (words_.total() > storageWords_) {
    // Grow by half again, so a slowly growing cut reallocates rarely.
    const uint32_t wanted = std::max(words_.total(), storageWords_ + storageWords_ / 2);
    glDeleteBuffers(1, &storage_);
    glCreateBuffers(1, &storage_);
    glNamedBufferStorage(storage_, GLsizeiptr(wanted) * 4, nullptr, GL_DYNAMIC_STORAGE_BIT);
    storageWords_ = wanted;
  }
  // Header, masks and hit counts are zeroed on the GPU; the lists need no clearing (the counters say what is
  // valid).
  // The last frame's rays wrote them with incoherent stores: the clear and the header update wait for those
  // (end() issues this barrier too, but a discarded or skipped frame does not).
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  const GLuint zero = 0;
  glClearNamedBufferSubData(storage_, GL_R32UI, 0, GLsizeiptr(words_.usedList()) * 4, GL_RED_INTEGER,
                            GL_UNSIGNED_INT, &zero);
  if (hitThreshold > 0)
    glClearNamedBufferSubData(storage_, GL_R32UI, GLintptr(words_.hits()) * 4,
                              GLsizeiptr(words_.total() - words_.hits()) * 4, GL_RED_INTEGER, GL_UNSIGNED_INT,
                              &zero);
  uint32_t header[kFeedbackHeaderWords] = {};
  header[kFeedbackUsedCapacity] = words_.usedCapacity;
  header[kFeedbackRequestedCapacity] = words_.requestedCapacity;
  header[kFeedbackMaskWords] = words_.maskWords;
  header[kFeedbackHitCapacity] = words_.hitCapacity;
  header[kFeedbackHitThreshold] = hitThreshold;
  glNamedBufferSubData(storage_, 0, sizeof header, header);
  inFrame_ = true;
}

void FeedbackBuffer::bind() const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, kFeedbackBinding, storage_);
}

void FeedbackBuffer::end(uint64_t frame) {
  if (!inFrame_) throw Error("FeedbackBuffer::end: no frame begun");
  inFrame_ = false;
  if (inFlightCount_ == ring_.size()) {
    ++skipped_;
    return;
  }
  Slot& s = ring_[(oldest_ + inFlightCount_) % ring_.size()];
  // The rays wrote with atomics and stores; the copies read what they wrote.
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  constexpr GLsizeiptr kHeaderBytes = kFeedbackHeaderWords * 4;
  glCopyNamedBufferSubData(storage_, s.buffer, 0, 0, kHeaderBytes);
  glCopyNamedBufferSubData(storage_, s.buffer, GLintptr(words_.usedList()) * 4, kHeaderBytes,
                           GLsizeiptr(words_.hits() - words_.usedList()) * 4);
  s.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  glFlush();  // so that the fence is submitted and can signal without a later wait flushing it
  s.frame = frame;
  ++inFlightCount_;
  checkGlError("FeedbackBuffer::end");
}

void FeedbackBuffer::discard() {
  if (!inFrame_) throw Error("FeedbackBuffer::discard: no frame begun");
  inFrame_ = false;
}

std::optional<FeedbackReadback> FeedbackBuffer::poll() {
  if (inFlightCount_ == 0) return std::nullopt;
  Slot& s = ring_[oldest_];
  if (!probe_->signaled(s.fence)) return std::nullopt;
  glDeleteSync(s.fence);
  s.fence = nullptr;
  oldest_ = (oldest_ + 1) % uint32_t(ring_.size());
  --inFlightCount_;

  const uint32_t* w = s.mapped;
  const uint32_t usedCapacity = w[kFeedbackUsedCapacity], requestedCapacity = w[kFeedbackRequestedCapacity];
  const uint32_t hitCapacity = w[kFeedbackHitCapacity];
  const uint32_t used = w[kFeedbackUsedCount], requested = w[kFeedbackRequestedCount];
  const uint32_t hits = w[kFeedbackHitCount];
  const uint32_t* usedList = w + kFeedbackHeaderWords;
  const uint32_t* requestedList = usedList + usedCapacity;
  const uint32_t* hitList = requestedList + requestedCapacity;
  FeedbackReadback r;
  r.frame = s.frame;
  r.usedLeaves.assign(usedList, usedList + std::min(used, usedCapacity));
  r.requestedLeaves.assign(requestedList, requestedList + std::min(requested, requestedCapacity));
  r.hitLeaves.assign(hitList, hitList + std::min(hits, hitCapacity));
  r.usedDropped = used > usedCapacity ? used - usedCapacity : 0;
  r.requestedDropped = requested > requestedCapacity ? requested - requestedCapacity : 0;
  r.hitDropped = hits > hitCapacity ? hits - hitCapacity : 0;
  return r;
}

}  // namespace ropecast
