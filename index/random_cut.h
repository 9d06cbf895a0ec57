// Random cuts for tests, fuzzing and `ropecast bench index`: reproducible from a seed. Pure function; any
// thread.
#pragma once

#include <cstdint>

#include "index/cut.h"

namespace ropecast {

struct RandomCutParams {
  uint64_t seed = 1;
  uint32_t targetLeaves =
      1000;                    // splitting stops once the cut has at least this many leaves (or cannot split)
  uint32_t maxDepth = 8;       // no leaf deeper than this (<= kCutMaxDepth)
  float emptyFraction = 0.3f;  // probability that a leaf is Empty
};

// Starts from the root and splits leaves picked at random (any leaf shallower than maxDepth) into their 8
// children, so depths vary widely across the cube. Data leaves get distinct brick slots 0, 1, 2, ...
Cut makeRandomCut(const RandomCutParams& params);

}  // namespace ropecast
