// The ray cast's feedback buffer (GigaVoxels-style usage and miss feedback, Crassin et al. 2009, Sect. 5;
// docs/RENDERING.md "Feedback"), one std430 array of 32-bit words laid out once for C++
// (render/feedback_buffer.cpp clears, sizes and reads it back) and GLSL (shaders/feedback.glsl writes it
// through the shader loader's textual #include). Layout only; any thread.
//
// Words, from 0:
//   header     kFeedbackHeaderWords words: the three counters, the three list capacities, the mask length,
//              the hit threshold
//   used mask  maskWords words: bit i of word i / 32 set when cut leaf i was used this frame
//   req. mask  maskWords words: the same for requests
//   used list  usedCapacity words: leaf indices in the order their bits were first set
//   req. list  requestedCapacity words
//   hit list   hitCapacity words: leaves in which hitThreshold rays stopped (at the isosurface, or by early
//              ray termination), in the order they reached it
//   hits       32 maskWords words: word i counts the rays that stopped in cut leaf i (up to the threshold;
//              racing rays may pass it), not read back
// A counter counts every leaf whose bit was set (or whose hits reached the threshold), also past its list's
// capacity (those are not stored), so dropped = counter - capacity.
#ifndef ROPECAST_SHADERS_FEEDBACK_LAYOUT_H
#define ROPECAST_SHADERS_FEEDBACK_LAYOUT_H

#ifdef __cplusplus
#include <cstdint>

namespace ropecast {
#define FEEDBACK_CONST inline constexpr std::uint32_t
#else
#define FEEDBACK_CONST const uint
#endif

// The shader storage binding point of the buffer.
FEEDBACK_CONST kFeedbackBinding = 1u;

// Header words.
FEEDBACK_CONST kFeedbackUsedCount = 0u;          // leaves used (bits set in the used mask)
FEEDBACK_CONST kFeedbackRequestedCount = 1u;     // leaves requested
FEEDBACK_CONST kFeedbackUsedCapacity = 2u;       // entries of the used list
FEEDBACK_CONST kFeedbackRequestedCapacity = 3u;  // entries of the requested list
FEEDBACK_CONST kFeedbackMaskWords = 4u;          // words per mask: ceil(leaf count / 32)
FEEDBACK_CONST kFeedbackHitCount = 5u;           // leaves whose hits reached the threshold
FEEDBACK_CONST kFeedbackHitCapacity = 6u;        // entries of the hit list
FEEDBACK_CONST kFeedbackHitThreshold = 7u;       // rays that make a leaf a hit; 0: hits are not counted
FEEDBACK_CONST kFeedbackHeaderWords = 8u;

#ifdef __cplusplus
// The first word of each part, and the buffer's length, for a frame's mask length and capacities.
struct FeedbackWords {
  std::uint32_t maskWords = 0, usedCapacity = 0, requestedCapacity = 0, hitCapacity = 0;

  std::uint32_t usedMask() const { return kFeedbackHeaderWords; }
  std::uint32_t requestedMask() const { return kFeedbackHeaderWords + maskWords; }
  std::uint32_t usedList() const { return kFeedbackHeaderWords + 2 * maskWords; }
  std::uint32_t requestedList() const { return usedList() + usedCapacity; }
  std::uint32_t hitList() const { return requestedList() + requestedCapacity; }
  std::uint32_t hits() const { return hitList() + hitCapacity; }
  std::uint32_t total() const { return hits() + 32 * maskWords; }
};

inline constexpr std::uint32_t feedbackMaskWords(std::uint32_t leafCount) {
  return (leafCount + 31u) / 32u;
}
}  // namespace ropecast
#endif

#undef FEEDBACK_CONST

#endif  // ROPECAST_SHADERS_FEEDBACK_LAYOUT_H
