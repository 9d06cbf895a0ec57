// What the rays say they needed (docs/RENDERING.md "Feedback"; Crassin et al. 2009, Sect. 5): each ray marks
// the data leaves of the cut it sampled as used, and requests at most one leaf, the first it sampled whose
// level is coarser than the ray wants there. A ray that stops (at the isosurface, or by early ray termination)
// also counts a hit for the leaf it stopped in; a leaf enough rays stopped in is visible without an occlusion
// query. Marks are bits over the cut's leaves (RopeLeaf.leafIndex); the
// invocation that sets a bit first appends the leaf to a short list, which is what the CPU reads back
// (render/feedback_buffer.h). Included by shaders/raycast_common.glsl under RAYCAST_FEEDBACK only, so the
// variant without feedback has none of this. No #version line.

#include "shaders/feedback_layout.h"

layout(std430, binding = kFeedbackBinding) buffer FeedbackWordsBlock {
  uint feedbackWords[];  // shaders/feedback_layout.h
};

// Sets the leaf's bit in the mask at word maskBase; the first to set it appends the leaf to its list.
void feedbackMark(uint maskBase, uint counter, uint capacityWord, uint listBase, uint leafIndex) {
  uint word = leafIndex / 32u;
  if (word >= feedbackWords[kFeedbackMaskWords]) return;  // a leaf past the frame's cut
  uint bit = 1u << (leafIndex % 32u);
  // Most leaves are marked by many rays: a plain read spares the atomic once the bit is seen set (a stale
  // read only costs the atomic).
  if ((feedbackWords[maskBase + word] & bit) != 0u) return;
  if ((atomicOr(feedbackWords[maskBase + word], bit) & bit) != 0u) return;
  uint entry = atomicAdd(feedbackWords[counter], 1u);
  if (entry < feedbackWords[capacityWord]) feedbackWords[listBase + entry] = leafIndex;
}

// Whether a ray wants a finer level than the leaf's at its entry into the leaf: one voxel of level L covers
// more than 1 / voxelsPerPixel pixels, i.e. 2^L R > d with R = raycast.feedbackRequestDistance and d the
// distance from the eye (docs/RENDERING.md "Feedback").
bool feedbackWantsFiner(uint depth, float tEnter, float t0) {
  uint level = raycast.maxDepth - depth;
  if (level == 0u) return false;
  float d = max(max(tEnter, t0), raycast.feedbackMinDistance);
  return ldexp(raycast.feedbackRequestDistance, int(level)) > d;
}

// The feedback of one ray: whether it has made its request.
struct RayFeedback {
  bool requested;
};

RayFeedback rayFeedbackBegin() { return RayFeedback(false); }

// The ray took a sample in the leaf (before it ended): used, and the ray's request if it is the first leaf
// that wants finer data.
void feedbackSampled(inout RayFeedback fb, uint leafIndex, bool wantsFiner) {
  uint maskWords = feedbackWords[kFeedbackMaskWords];
  uint usedList = kFeedbackHeaderWords + 2u * maskWords;
  feedbackMark(kFeedbackHeaderWords, kFeedbackUsedCount, kFeedbackUsedCapacity, usedList, leafIndex);
  if (fb.requested || !wantsFiner) return;
  fb.requested = true;
  feedbackMark(kFeedbackHeaderWords + maskWords, kFeedbackRequestedCount, kFeedbackRequestedCapacity,
               usedList + feedbackWords[kFeedbackUsedCapacity], leafIndex);
}

// The ray stopped in the leaf (RayResult.stopDepth is a sample of it): its hit is counted, and the ray that brings the count to the
// threshold lists the leaf. Counting stops at the threshold (racing rays may pass it), so most rays of a
// large leaf only read its count.
void feedbackHit(uint leafIndex) {
  uint threshold = feedbackWords[kFeedbackHitThreshold];
  uint maskWords = feedbackWords[kFeedbackMaskWords];
  if (threshold == 0u || leafIndex / 32u >= maskWords) return;
  uint hitList = kFeedbackHeaderWords + 2u * maskWords + feedbackWords[kFeedbackUsedCapacity] +
                 feedbackWords[kFeedbackRequestedCapacity];
  uint hits = hitList + feedbackWords[kFeedbackHitCapacity] + leafIndex;
  if (feedbackWords[hits] >= threshold) return;
  if (atomicAdd(feedbackWords[hits], 1u) + 1u != threshold) return;
  uint entry = atomicAdd(feedbackWords[kFeedbackHitCount], 1u);
  if (entry < feedbackWords[kFeedbackHitCapacity]) feedbackWords[hitList + entry] = leafIndex;
}
