// What the rays' latest answer (RayFeedback) tells the occlusion queries (VisibilityTracker) about the data
// leaves of the last cut, with occlusion and feedback both on:
// - a leaf no ray sampled is hidden without a query (markUnseen);
// - a leaf in which enough rays stopped is visible, as its query would say (markHit);
// - a leaf the rays sampled otherwise keeps its mark until its query answers: fewer rays than the visibility
//   threshold may have passed through it, and a query would call it hidden (withdrawing an earlier "unused"
//   at once refined such leaves along a camera path only for the next query to collapse them again).
// A node collapsed on this view (CollapseGuard) is left to its own query, drawn part by part: its coarse data
// shows surfaces that its hidden children's finer data does not (holes closed by filtering), so the rays that
// stop in it say nothing about those children.
//
// A plain function over the three; the render thread, before VisibilityTracker::propagate.
#pragma once

#include <cstdint>
#include <span>

#include "loader/collapse_guard.h"
#include "loader/ray_feedback.h"
#include "occlusion/visibility_tracker.h"

namespace ropecast {

void markVisibilityFromRays(std::span<const NodeKey> dataLeaves, const RayFeedback& rays,
                            const CollapseGuard& collapses, uint64_t frame, VisibilityTracker& visibility);

}  // namespace ropecast
