// What the rays' latest answer (RayFeedback) tells the occlusion queries (VisibilityTracker) about the data
// leaves of the last cut, with occlusion and feedback both on:
// - a leaf no ray sampled is hidden without a query (markUnseen);
// - a leaf a newer answer found sampled loses that mark (markSeen): from far away no ray may reach the root,
//   which from near fills the screen, and the mark would keep it from refining, and the cut with it
//   converged, until it expired;
// - a leaf in which enough rays stopped is visible, as its query would say (markHit).
// A node collapsed on this view (CollapseGuard) is left to its own query, drawn part by part: its coarse data
// shows surfaces that its hidden children's finer data does not (holes closed by filtering), so the rays that
// sample or stop in it say nothing about those children; a ray's use would withdraw the mark that keeps it
// collapsed, and the ray's request would refine it again.
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
