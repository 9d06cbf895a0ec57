// Extraction of one resolution level of a bricked octree as a raw volume (`ropecast extract`): x fastest,
// little-endian, in the volume's original type (int8/uint8/int16/uint16 exactly as converted; uint32/int32
// through ValueMapping, rounded to the nearest integer: exact where their range fit 16 bits; float32/float64
// dequantized through ValueMapping). Empty (discarded) nodes read as stored value 0. Reads one z-row of
// bricks at a time, and of a region only the bricks that overlap it. In the file's order: regions and voxels
// are the file's indices, and where a store keeps x reversed (BrickSourceInfo::xReversed) its rows are
// written back to front, so that the volume comes out as the file held it.
//
// Threads: any thread; the BrickSource may be shared with other readers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "store/brick_source.h"

namespace ropecast {

// The voxels [begin, end) per axis of a level (`extract --crop`); by default the whole level (an end past the
// level's dims stands for them).
struct LevelRegion {
  glm::u32vec3 begin{0};
  glm::u32vec3 end{UINT32_MAX};
};

// The dims of level `level` of the store. Throws UsageError for a level the store does not have.
glm::u32vec3 levelDimsOf(const BrickSource& source, uint32_t level);

// Calls `sink(bytes)` with consecutive pieces of the region of the level as a raw volume (whole slices of the
// region, in z order). Reads only the bricks that overlap the region. Throws UsageError for a level the store
// does not have, or a region that is empty or leaves the level.
void extractLevel(const BrickSource& source, uint32_t level,
                  const std::function<void(std::span<const std::byte>)>& sink,
                  const LevelRegion& region = {});

// The region in memory (tests, small volumes).
std::vector<std::byte> extractLevelBytes(const BrickSource& source, uint32_t level,
                                         const LevelRegion& region = {});

// The value of one voxel (the file's indices) of a level in data units, as extractLevel writes it (an integer
// type's exactly; a float's as the store keeps it: quantized to 16 bits over its value range). Reads the one
// brick that holds it. Throws UsageError, naming the level, for a voxel outside it.
double voxelValue(const BrickSource& source, uint32_t level, glm::u32vec3 voxel);

// voxelValue one voxel after another (the viewer's probe), keeping the last brick read: the voxels of one
// brick cost one read. One caller at a time; the BrickSource may be shared with other readers.
class VoxelReader {
 public:
  explicit VoxelReader(const BrickSource& source) : source_(source) {}
  double value(uint32_t level, glm::u32vec3 voxel);
  // Whether value(level, voxel) would read nothing: the voxel lies in the brick kept.
  bool holds(uint32_t level, glm::u32vec3 voxel) const;

 private:
  // The node whose brick holds the voxel (the store's index along x). Throws as value.
  NodeKey nodeOf(uint32_t level, glm::u32vec3& voxel) const;

  const BrickSource& source_;
  std::optional<NodeKey> cached_;
  std::vector<std::byte> brick_;
};

// Writes `header` (may be empty) and the region to `output` under a temporary name, renamed when complete.
void extractLevelToFile(const BrickSource& source, uint32_t level, const std::filesystem::path& output,
                        const LevelRegion& region = {}, std::string_view header = {});

// The header of a NRRD file whose attached data is the region of the level as extractLevel writes it (raw,
// little-endian, the original type): its sizes, and where it lies in the world (docs/RENDERING.md "Spaces"),
// in the LPS frame: space directions (the file's axes, those of the store with x turned back where it keeps x
// reversed, times the level's spacing, 2^level s) and the space origin of its first sample. Throws UsageError
// as extractLevel.
std::string nrrdHeaderOf(const BrickSource& source, uint32_t level, const LevelRegion& region = {});

// The bytes of a NIfTI-1 single file's header (348 bytes and 4 of extension flags, kNiftiHeaderBytes) whose
// data is the region as extractLevel writes it: sizes, datatype, spacing (pixdim) and an sform that places
// the samples as nrrdHeaderOf does, in NIfTI's RAS. Throws UsageError as extractLevel, or for a region of
// more than 32767 samples along an axis (NIfTI-1's limit).
inline constexpr size_t kNiftiHeaderBytes = 352;
std::string niftiHeaderOf(const BrickSource& source, uint32_t level, const LevelRegion& region = {});

}  // namespace ropecast
