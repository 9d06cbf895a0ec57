// FeedbackBuffer: what the rays of a frame said they needed (docs/RENDERING.md "Feedback"; Crassin et al.
// 2009, Sect. 5), from the GPU to the CPU without a stall. Owns the shader storage buffer the ray cast writes
// (shaders/feedback_layout.h: bitmasks and hit counts over the cut's leaves, counters, and three short lists,
// used, requested and hit leaves) and a ring of persistently mapped readback buffers. A frame:
//   begin(leafCount, hitThreshold)  clears the masks and counts (on the GPU) for a cut of leafCount leaves;
//   the ray cast      RaycastFrame::feedback = this (RaycastPass binds it);
//   end(frame)        copies counters and lists into a free ring slot and fences the copy; with every slot
//                     still in flight it skips the frame's readback (counted) rather than wait;
//   poll()            the oldest frame whose fence has signaled, else nothing; never waits;
//   discard()         instead of end(): no readback (a draw that only compiles the shader).
// Leaf indices are those of the frame's cut (RopeLeaf.leafIndex): the caller keeps the cuts of the frames in
// flight to map them to nodes.
//
// Owns GL objects: render thread only, with the GlContext current.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "render/gl_fence.h"
#include "shaders/feedback_layout.h"

namespace ropecast {

// One frame's feedback as read back. Lists hold at most the buffer's capacities; dropped = how many more
// leaves the rays marked than the list could hold.
struct FeedbackReadback {
  uint64_t frame = 0;
  std::vector<uint32_t> usedLeaves;       // leaf indices in that frame's cut, each once, in no order
  std::vector<uint32_t> requestedLeaves;  // each once, in no order
  // Leaves in which at least the frame's hit threshold of rays stopped (at the isosurface, or by early ray
  // termination); each once, in no order. Empty with a threshold of 0.
  std::vector<uint32_t> hitLeaves;
  uint64_t usedDropped = 0;
  uint64_t requestedDropped = 0;
  uint64_t hitDropped = 0;
};

struct FeedbackBufferConfig {
  uint32_t usedCapacity = 16384;      // entries of the used list
  uint32_t requestedCapacity = 4096;  // entries of the requested list
  uint32_t ringSize = 3;              // readback buffers: frames in flight at most
  uint32_t hitCapacity = 16384;       // entries of the hit list
};

class FeedbackBuffer {
 public:
  // Throws ropecast::Error for a zero capacity or ring size. A null probe asks GL.
  explicit FeedbackBuffer(const FeedbackBufferConfig& config = {},
                          std::unique_ptr<FenceProbe> probe = nullptr);
  ~FeedbackBuffer();
  FeedbackBuffer(const FeedbackBuffer&) = delete;
  FeedbackBuffer& operator=(const FeedbackBuffer&) = delete;

  // Starts a frame over a cut of leafCount leaves: zero masks, counts and counters
  // (glClearNamedBufferSubData) and a 32-byte header; the rays do not record leaves of index leafCount or
  // more. A leaf in which hitThreshold rays stop is listed as a hit (0: hits are not counted). Throws
  // ropecast::Error if a frame is already open.
  void begin(uint32_t leafCount, uint32_t hitThreshold = 0);
  // Binds the storage buffer to kFeedbackBinding (RaycastPass calls it).
  void bind() const;
  // Ends the frame: queues the readback of its counters and lists, fenced. Skips it when all ring slots are
  // in flight. Throws ropecast::Error without an open frame.
  void end(uint64_t frame);
  // Ends the frame without a readback: for a draw that only makes the driver compile the shader
  // (FrameRenderer::prepare). Throws ropecast::Error without an open frame.
  void discard();
  // The oldest frame whose readback has arrived, or nothing; never waits.
  std::optional<FeedbackReadback> poll();

  // Tests: ask `probe` whether a fence signaled instead of GL.
  void setFenceProbe(std::unique_ptr<FenceProbe> probe) { probe_ = std::move(probe); }
  bool inFrame() const { return inFrame_; }
  uint32_t inFlight() const { return inFlightCount_; }
  // Frames whose readback end() skipped because the ring was full.
  uint64_t skippedReadbacks() const { return skipped_; }
  const FeedbackBufferConfig& config() const { return config_; }

 private:
  struct Slot {
    uint32_t buffer = 0;
    const uint32_t* mapped = nullptr;  // the header and the three lists
    GlSync fence = nullptr;
    uint64_t frame = 0;
  };

  FeedbackBufferConfig config_;
  std::unique_ptr<FenceProbe> probe_;
  uint32_t storage_ = 0;       // the shader storage buffer
  uint32_t storageWords_ = 0;  // its allocated length
  FeedbackWords words_;        // this frame's layout
  bool inFrame_ = false;
  std::vector<Slot> ring_;
  uint32_t oldest_ = 0;  // ring index of the oldest slot in flight
  uint32_t inFlightCount_ = 0;
  uint64_t skipped_ = 0;
};

}  // namespace ropecast
