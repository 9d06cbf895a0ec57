// Extraction of one resolution level of a bricked octree as a raw volume (`ropecast extract`): x fastest,
// little-endian, in the volume's original type (int8/uint8/int16/uint16 exactly as converted; uint32/int32
// through ValueMapping, rounded to the nearest integer: exact where their range fit 16 bits; float32/float64
// dequantized through ValueMapping). Empty (discarded) nodes read as stored value 0. Reads one z-row of
// bricks at a time.
//
// Threads: any thread; the BrickSource may be shared with other readers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <vector>

#include "store/brick_source.h"

namespace ropecast {

// Calls `sink(bytes)` with consecutive pieces of the level's raw volume (whole slices, in z order).
void extractLevel(const BrickSource& source, uint32_t level,
                  const std::function<void(std::span<const std::byte>)>& sink);

// The whole level in memory (tests, small volumes).
std::vector<std::byte> extractLevelBytes(const BrickSource& source, uint32_t level);

// Writes the level to `output` under a temporary name, renamed when complete.
void extractLevelToFile(const BrickSource& source, uint32_t level, const std::filesystem::path& output);

}  // namespace ropecast
