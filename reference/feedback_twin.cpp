#include "reference/feedback_twin.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include <glm/trigonometric.hpp>

namespace ropecast {

namespace {

constexpr size_t kNever = std::numeric_limits<size_t>::max();

// One ray's leaves in walk order, each with the global index (over the ray's samples) of its first sample,
// or of the next sample when it has none.
struct RayLeaves {
  std::vector<size_t> position;
  std::vector<size_t> count;
};

RayLeaves indexSamples(const MirrorRayTrace& trace) {
  RayLeaves r;
  size_t g = 0;
  for (size_t v = 0; v < trace.leaves.size(); ++v) {
    r.position.push_back(g);
    r.count.push_back(trace.leaves[v].samples.size());
    g += trace.leaves[v].samples.size();
  }
  return r;
}

std::vector<uint32_t> sorted(const std::set<uint32_t>& s) {
  return {s.begin(), s.end()};
}

}  // namespace

double feedbackVoxelPixels(uint32_t level, double distance, glm::dvec3 spacing, double fovYDeg,
                           uint32_t height) {
  const double minSpacing = std::min({spacing.x, spacing.y, spacing.z});
  const double maxSpacing = std::max({spacing.x, spacing.y, spacing.z});
  const double d = std::max(distance, 0.5 * minSpacing);
  const double tanHalf = std::tan(glm::radians(fovYDeg) * 0.5);
  return std::ldexp(1.0, int(level)) * maxSpacing / (2.0 * d * tanHalf) * double(height);
}

FeedbackBounds feedbackOfTraces(const std::vector<MirrorRayTrace>& traces, const BrickSourceInfo& volume,
                                const CpuRenderInput& input, double voxelsPerPixel,
                                const FeedbackTolerance& tol, uint32_t hitThreshold) {
  const bool iso = input.params.mode == RenderMode::Iso;
  const bool mip = isIntensityProjection(input.params.mode);  // rays that end only where nothing is left
  const bool aip = input.params.mode == RenderMode::Aip;      // rays that never end before their exit
  const bool slice = input.params.mode == RenderMode::Slice;  // rays of one sample, which stops nothing
  const double ert = input.params.ert;
  const glm::dvec3 spacing = volume.volume.spacing;
  const double cubeExtent = double(volume.layout.cubeSamples()) * std::max({spacing.x, spacing.y, spacing.z});
  std::set<uint32_t> sureUsed, possibleUsed, sureRequested, possibleRequested;
  // Per leaf, the rays that surely stop in it and those that may.
  std::map<uint32_t, uint32_t> sureHits, possibleHits;
  FeedbackBounds out;

  for (const MirrorRayTrace& trace : traces) {
    if (!trace.entered || trace.leaves.empty()) continue;
    const RayLeaves rl = indexSamples(trace);
    const size_t leafCount = trace.leaves.size();

    // Samples within rounding of a leaf border (tolerance.relative): in float the sample may fall in the
    // neighbouring leaf (sampled at its level), or a sample of the leaf's grid just past the border may be
    // taken too. The leaves on either side may gain or lose that one sample, and its value is uncertain.
    std::vector<bool> tie(leafCount, false);
    std::set<size_t> tieSamples;  // global indices of the samples next to such a border
    if (tol.relative > 0.0) {
      for (size_t v = 0; v < leafCount; ++v) {
        const MirrorLeafVisit& l = trace.leaves[v];
        const auto at = [&](double k) { return trace.t0 + k * l.dt; };
        const auto near = [&](double a, double b) {
          return std::abs(a - b) <= tol.relative * (std::abs(b) + cubeExtent);
        };
        const size_t gridCount = l.gridSampleCount();
        const double kEnd = l.kBegin + double(gridCount);
        const double tStop = std::min(l.tExit, trace.t1);
        const size_t first = rl.position[v], pastGrid = first + gridCount, past = first + rl.count[v];
        if (!l.firstLeaf && (near(at(l.kBegin), l.tEnter) || near(at(l.kBegin - 1.0), l.tEnter))) {
          tie[v] = true;
          if (first > 0) tieSamples.insert(first - 1);
          tieSamples.insert(first);
        }
        // A grid sample at the leaf's end also decides whether the sample at its end is taken.
        if (near(at(kEnd), tStop) || near(at(kEnd - 1.0), tStop)) {
          tie[v] = true;
          if (pastGrid > 0) tieSamples.insert(pastGrid - 1);
          tieSamples.insert(pastGrid);
          tieSamples.insert(past);
        }
      }
      // A leaf keeps at least one sample unless it has at most two (one lost at either border).
      for (size_t v = 0; v < leafCount; ++v) {
        const size_t gridCount = trace.leaves[v].gridSampleCount();
        const size_t first = rl.position[v], pastGrid = first + gridCount;
        const bool touched =
            tieSamples.count(first) > 0 || (pastGrid > 0 && tieSamples.count(pastGrid - 1) > 0);
        tie[v] = (tie[v] || touched) && gridCount <= 2;
      }
    }
    // MIP: a leaf whose largest value is within rounding of the ray's maximum may be skipped or sampled.
    if (mip && tol.value > 0.0)
      for (size_t v = 0; v < leafCount; ++v)
        if (std::abs(trace.leaves[v].maximumMargin) <= tol.value) tie[v] = true;
    // The iso samples at leaves' ends (docs/RENDERING.md "Isosurface"), taken when the ray's previous sample
    // lies more than a texel before the end. Within the position errors' texels of one, the shader may decide
    // either way: the sample is uncertain, and so is every leaf-end decision after it up to the next grid
    // sample, which measure from another previous sample; a leaf without grid samples there may be sampled at
    // its end although the mirror did not. Exact positions: the mirror's decisions.
    const bool positionsExact = !(tol.relative > 0.0);
    std::vector<bool> counted(rl.position.empty() ? 0 : rl.position.back() + rl.count.back(), true);
    std::vector<bool> mayBeSampledAtEnd(leafCount, false);
    {
      size_t g = 0;
      bool unsettled = false;
      double tPrev = trace.t0;
      for (size_t v = 0; v < leafCount; ++v) {
        const MirrorLeafVisit& l = trace.leaves[v];
        if (l.gridSampleCount() == 0) mayBeSampledAtEnd[v] = unsettled;
        for (const MirrorSample& s : l.samples) {
          if (!s.atLeafEnd) {
            unsettled = false;
            tPrev = s.t;
            ++g;
            continue;
          }
          const double texelsPerT = s.leafEndGapTexels / std::max(s.t - tPrev, 1e-300);
          const double error =
              tol.relative * (std::abs(s.t) + std::abs(tPrev) + 2.0 * cubeExtent) * texelsPerT;
          const bool marginal = !positionsExact && std::abs(s.leafEndGapTexels - 1.0) <= error;
          counted[g] = s.leafEndTaken || marginal;
          if (counted[g] && (marginal || unsettled)) tieSamples.insert(g);
          unsettled = unsettled || marginal;
          if (s.leafEndTaken) tPrev = s.t;
          ++g;
        }
      }
    }

    // Where the ray may end (earliest) and where it surely has ended (latest), as global sample indices.
    size_t earliest = kNever, latest = kNever;
    {
      size_t g = 0;
      bool hasPrev = false, prevUncertain = false, opacityUnknown = false;
      double fPrev = 0.0;
      for (const MirrorLeafVisit& v : trace.leaves)
        for (const MirrorSample& s : v.samples) {
          if (!counted[g]) {
            ++g;
            continue;
          }
          bool possible = false, sure = false;
          const bool uncertain = tieSamples.count(g) > 0;
          if (iso) {
            if (hasPrev) {
              const bool crosses = (s.f >= 0.0) != (fPrev >= 0.0);
              const bool close =
                  std::abs(s.f) < tol.value || std::abs(fPrev) < tol.value || uncertain || prevUncertain;
              possible = crosses || close;
              sure = crosses && !close;
            } else if (trace.capped) {
              // The first sample of a ray that entered through a capped cut ends it inside the surface.
              const bool inside = s.f >= 0.0;
              const bool close = std::abs(s.f) < tol.value || uncertain;
              possible = inside || close;
              sure = inside && !close;
            }
            hasPrev = true;
            fPrev = s.f;
            prevUncertain = uncertain;
          } else if (!mip && !aip && !slice) {
            // An uncertain sample's opacity is unknown, and so is the opacity accumulated from it on.
            opacityUnknown = opacityUnknown || uncertain;
            possible = uncertain || (s.addsOpacity && s.alpha >= ert - tol.alpha);
            sure = !opacityUnknown && s.addsOpacity && s.alpha >= ert + tol.alpha;
          }
          if (possible && earliest == kNever) earliest = g;
          if (sure && latest == kNever) latest = g;
          ++g;
        }
    }
    if (earliest != latest || std::find(tie.begin(), tie.end(), true) != tie.end()) ++out.uncertainRays;

    // The hit: the leaf of the sample the ray stops at. It may stop at any sample from the earliest to the
    // latest end, and a sample next to a leaf border may fall in the leaf on the other side.
    if (hitThreshold > 0 && earliest != kNever) {
      const size_t last = latest == kNever ? rl.position.back() + rl.count.back() : latest + 1;
      std::set<uint32_t> mayStopIn;
      std::optional<uint32_t> surelyStopsIn;
      for (size_t v = 0; v < leafCount; ++v)
        for (size_t g = rl.position[v]; g < rl.position[v] + rl.count[v]; ++g) {
          if (g < earliest || g >= last) continue;
          const bool uncertain = tie[v] || tieSamples.count(g) > 0;
          mayStopIn.insert(trace.leaves[v].leafIndex);
          if (uncertain && v > 0) mayStopIn.insert(trace.leaves[v - 1].leafIndex);
          if (uncertain && v + 1 < leafCount) mayStopIn.insert(trace.leaves[v + 1].leafIndex);
          if (g == earliest && earliest == latest && !uncertain) surelyStopsIn = trace.leaves[v].leafIndex;
        }
      for (uint32_t leaf : mayStopIn) ++possibleHits[leaf];
      if (surelyStopsIn) ++sureHits[*surelyStopsIn];
    }

    // The rules. Sure: a leaf sampled no later than the earliest end; possible: no later than the latest.
    bool sureRequestOpen = true, possibleRequestOpen = true;
    for (size_t v = 0; v < leafCount; ++v) {
      const MirrorLeafVisit& l = trace.leaves[v];
      // The samples the shader surely takes in the leaf, and whether it may take one more at the leaf's end.
      const size_t gridCount = l.gridSampleCount();
      const size_t endIndex = rl.position[v] + gridCount;
      const bool endCounted = rl.count[v] > gridCount && counted[endIndex];
      const bool endSure = endCounted && tieSamples.count(endIndex) == 0;
      const size_t sureCount = gridCount + (endSure ? 1 : 0);
      const bool mayTakeMore = (endCounted && !endSure) || mayBeSampledAtEnd[v];
      const bool isSure = sureCount > 0 && rl.position[v] <= earliest && !tie[v];
      if (rl.position[v] > latest) break;
      if (sureCount == 0 && !mayTakeMore && !tie[v]) continue;  // a leaf the ray crossed between two samples
      if (isSure) sureUsed.insert(l.leafIndex);
      possibleUsed.insert(l.leafIndex);

      const uint32_t level = volume.layout.levelOfDepth(l.depth);
      const double pixels = level == 0 ? 0.0
                                       : feedbackVoxelPixels(level, std::max(l.tEnter, trace.t0), spacing,
                                                             input.camera.fovYDeg, input.height);
      const double ratio = pixels * voxelsPerPixel;  // a miss: ratio > 1
      const bool miss = level > 0 && ratio > 1.0;
      const bool marginal = level > 0 && std::abs(ratio - 1.0) <= tol.relative;
      // The ray's request is the first leaf that may be a miss: sure if that leaf surely is one and surely
      // sampled.
      if (sureRequestOpen && (miss || marginal)) {
        if (isSure && !marginal) sureRequested.insert(l.leafIndex);
        sureRequestOpen = false;
      }
      if (possibleRequestOpen && (miss || marginal)) {
        possibleRequested.insert(l.leafIndex);
        if (miss && !marginal && isSure) possibleRequestOpen = false;
      }
    }
  }
  const auto reaching = [hitThreshold](const std::map<uint32_t, uint32_t>& hits) {
    std::vector<uint32_t> leaves;
    for (const auto& [leaf, rays] : hits)
      if (rays >= hitThreshold) leaves.push_back(leaf);
    return leaves;
  };
  out.sure = {sorted(sureUsed), sorted(sureRequested), reaching(sureHits)};
  out.possible = {sorted(possibleUsed), sorted(possibleRequested), reaching(possibleHits)};
  return out;
}

FeedbackBounds mirrorFeedback(const RopeIndex& index, const BricksBySlot& bricks,
                              const BrickSourceInfo& volume, const CpuRenderInput& input,
                              double voxelsPerPixel, const FeedbackTolerance& tolerance,
                              uint32_t hitThreshold) {
  std::vector<MirrorRayTrace> traces;
  renderMirror(index, bricks, volume, input, &traces);
  return feedbackOfTraces(traces, volume, input, voxelsPerPixel, tolerance, hitThreshold);
}

}  // namespace ropecast
