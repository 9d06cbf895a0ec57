// The CPU twin of the ray cast's usage and miss feedback (docs/RENDERING.md "Feedback";
// shaders/feedback.glsl; Crassin et al. 2009, Sect. 5): the rules applied to the rays of the CPU mirror
// (reference/cpu_raycaster.h renderMirror, which reports per ray the leaves it sampled and where it ended).
// GL tests compare the GPU's sets with it. Pure CPU; any thread.
#pragma once

#include <cstdint>
#include <vector>

#include "reference/cpu_raycaster.h"

namespace ropecast {

// Leaf indices in the Cut's leaves, sorted, each once.
struct FeedbackSets {
  std::vector<uint32_t> usedLeaves;
  std::vector<uint32_t> requestedLeaves;
  std::vector<uint32_t> hitLeaves;  // leaves in which at least the hit threshold of rays stopped
};

// How far the GPU's float arithmetic and filtering may stray from the mirror's double before it can decide
// otherwise: a sample's side of the isosurface, early ray termination, which leaf a sample falls in, whether
// a leaf is coarser than wanted. Zero: the mirror's own decisions.
struct FeedbackTolerance {
  double value = 0.0;     // iso: |v - vIso| below which a sample's side is uncertain; MIP: |leaf's largest
                          // value - the ray's maximum| below which skipping the leaf is
  double alpha = 0.0;     // DVR: |A - ert| below which termination at a sample is uncertain
  double relative = 0.0;  // a sample within relative (t + cube extent) of a leaf border; a leaf whose
                          // pixels(L) voxelsPerPixel is within relative of 1; an iso sample at a leaf's
                          // end whose distance from the previous sample is within the texels those
                          // positions' errors make of one texel
};

// sure: what the rules give for every arithmetic within the tolerance; possible: what they may give for some.
// With zero tolerance both are the rules applied to the mirror's rays.
struct FeedbackBounds {
  FeedbackSets sure;
  FeedbackSets possible;
  size_t uncertainRays = 0;  // rays whose leaves or request the tolerance leaves open
};

// pixels(L) of docs/RENDERING.md "Feedback": the projected size of one level-L voxel at world distance
// `distance` from the eye (clamped below at 0.5 min spacing), in pixels of an image `height` high.
double feedbackVoxelPixels(uint32_t level, double distance, glm::dvec3 spacing, double fovYDeg,
                           uint32_t height);

// Renders the mirror of `input` with traces and applies the rules with the refinement target
// voxelsPerPixel and, for hits, hitThreshold (0: no hits, as the shader with a threshold of 0). Throws as
// renderMirror.
FeedbackBounds mirrorFeedback(const RopeIndex& index, const BricksBySlot& bricks,
                              const BrickSourceInfo& volume, const CpuRenderInput& input,
                              double voxelsPerPixel, const FeedbackTolerance& tolerance = {},
                              uint32_t hitThreshold = 0);

// The rules over traces renderMirror has made of `input`'s rays.
FeedbackBounds feedbackOfTraces(const std::vector<MirrorRayTrace>& traces, const BrickSourceInfo& volume,
                                const CpuRenderInput& input, double voxelsPerPixel,
                                const FeedbackTolerance& tolerance = {}, uint32_t hitThreshold = 0);

}  // namespace ropecast
