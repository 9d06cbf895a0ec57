// ValueHistogram: how a volume's values are distributed, counted over the root brick of its octree (the
// coarsest level, box-filtered: one brick read, however large the volume), in bins of data units. What the
// viewer draws behind its isovalue slider and transfer-function editor; an overview of where the values lie,
// not an exact count of the full-resolution samples (filtering narrows thin peaks). Plain data and a pure
// function; any thread (BrickSource reads are thread-safe).
#pragma once

#include <cstdint>
#include <vector>

#include "store/brick_source.h"

namespace ropecast {

struct ValueHistogram {
  double minValue = 0.0, maxValue = 1.0;  // data units: bin i covers [min + i w, min + (i + 1) w)
  std::vector<uint64_t> counts;           // samples per bin
  uint32_t level = 0;                     // the resolution level counted (docs/FORMAT.md)
};

// Counts the root brick's samples that lie inside the data (not the border, not the padding beyond the
// level's dims) into `bins` equal bins over [minValue, maxValue] (values outside clamp to the end bins).
// Throws ropecast::Error as readBrick does.
ValueHistogram coarseHistogram(const BrickSource& source, uint32_t bins, double minValue, double maxValue);

}  // namespace ropecast
