#include "store/extract.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <tuple>
#include <utility>

#include <glm/common.hpp>

#include "core/error.h"
#include "store/nifti_header.h"
#include "store/store_writer.h"
#include "store/volume_source.h"

namespace ropecast {

namespace {

// The data value of a stored sample as the integer type I: rounded to nearest, within I's range.
template <typename I>
I roundedData(uint16_t stored, const ValueMapping& mapping) {
  const double v = std::nearbyint(mapping.toData(stored));
  return I(std::clamp(v, double(std::numeric_limits<I>::min()), double(std::numeric_limits<I>::max())));
}

// The stored value of texel `index` of a brick (UInt8 or UInt16).
uint16_t storedTexel(std::span<const std::byte> brick, SampleType storedType, size_t index) {
  if (storedType == SampleType::UInt8) return uint16_t(brick[index]);
  uint16_t stored;
  std::memcpy(&stored, brick.data() + 2 * index, 2);
  return stored;
}

// Writes one stored sample in the original type.
void writeOriginal(uint16_t stored, SampleType type, const ValueMapping& mapping, std::byte* out) {
  switch (type) {
    case SampleType::UInt8:
      *out = std::byte(stored);
      return;
    case SampleType::Int8:
      *out = std::byte(uint8_t(int8_t(int32_t(stored) - 128)));
      return;
    case SampleType::UInt16:
      std::memcpy(out, &stored, 2);
      return;
    case SampleType::Int16: {
      const int16_t v = int16_t(int32_t(stored) - 32768);
      std::memcpy(out, &v, 2);
      return;
    }
    case SampleType::UInt32: {
      const uint32_t v = roundedData<uint32_t>(stored, mapping);
      std::memcpy(out, &v, 4);
      return;
    }
    case SampleType::Int32: {
      const int32_t v = roundedData<int32_t>(stored, mapping);
      std::memcpy(out, &v, 4);
      return;
    }
    case SampleType::Float32: {
      const float v = float(mapping.toData(stored));
      std::memcpy(out, &v, 4);
      return;
    }
    case SampleType::Float64: {
      const double v = mapping.toData(stored);
      std::memcpy(out, &v, 8);
      return;
    }
  }
}

}  // namespace

glm::u32vec3 levelDimsOf(const BrickSource& source, uint32_t level) {
  const OctreeLayout& layout = source.info().layout;
  if (level > layout.maxDepth)
    throw UsageError("extract: --level " + std::to_string(level) + ": the store has levels 0.." +
                     std::to_string(layout.maxDepth));
  return layout.levelDims(level);
}

void extractLevel(const BrickSource& source, uint32_t level,
                  const std::function<void(std::span<const std::byte>)>& sink, const LevelRegion& region) {
  const BrickSourceInfo& info = source.info();
  const OctreeLayout& layout = info.layout;
  const glm::u32vec3 levelDims = levelDimsOf(source, level);
  const uint32_t depth = layout.maxDepth - level, b = layout.brickSize, edge = layout.storedBrickEdge();
  glm::u32vec3 begin = region.begin, end = glm::min(region.end, levelDims);
  for (int axis = 0; axis < 3; ++axis)
    if (!(begin[axis] < end[axis]))
      throw UsageError("extract: the region from voxel " + formatDims(begin) + " to " + formatDims(end) +
                       " holds no voxel of level " + std::to_string(level) + " (" + formatDims(levelDims) +
                       ")");
  // The region is in the file's indices: where the store keeps x reversed, its x range is the mirror one, and
  // each row is written back to front.
  if (info.xReversed) std::tie(begin.x, end.x) = std::pair(levelDims.x - end.x, levelDims.x - begin.x);
  const glm::u32vec3 dims = end - begin;  // of the output
  const SampleType type = info.volume.type;
  const size_t outBytes = bytesPerSample(type), sliceBytes = size_t(dims.x) * dims.y * outBytes;
  std::vector<std::byte> brick(source.brickBytes());
  std::vector<std::byte> slab;
  for (uint32_t row = begin.z / b; row * b < end.z; ++row) {
    // The row's slices inside the region, [za, zb) in level voxels.
    const uint32_t za = std::max(row * b, begin.z), zb = std::min((row + 1) * b, end.z);
    slab.assign(size_t(zb - za) * sliceBytes, std::byte{0});
    for (uint32_t cy = begin.y / b; cy * b < end.y; ++cy) {
      const uint32_t ya = std::max(cy * b, begin.y), yb = std::min((cy + 1) * b, end.y);
      for (uint32_t cx = begin.x / b; cx * b < end.x; ++cx) {
        const uint32_t xa = std::max(cx * b, begin.x), xb = std::min((cx + 1) * b, end.x);
        source.readBrick({depth, {cx, cy, row}}, brick);
        for (uint32_t z = za; z < zb; ++z)
          for (uint32_t y = ya; y < yb; ++y) {
            // The brick's sample (xa, y, z), behind its border.
            const size_t in =
                (size_t(z - row * b + kBrickBorder) * edge + (y - cy * b + kBrickBorder)) * edge +
                (xa - cx * b + kBrickBorder);
            std::byte* out = slab.data() + (z - za) * sliceBytes +
                             ((size_t(y) - begin.y) * dims.x + (xa - begin.x)) * outBytes;
            for (uint32_t i = 0; i < xb - xa; ++i)
              writeOriginal(storedTexel(brick, info.storedType, in + i), type, info.mapping,
                            out + i * outBytes);
          }
      }
    }
    if (info.xReversed)
      for (size_t rowStart = 0; rowStart < slab.size(); rowStart += size_t(dims.x) * outBytes)
        for (size_t i = 0, j = dims.x - 1; i < j; ++i, --j)
          std::swap_ranges(slab.begin() + ptrdiff_t(rowStart + i * outBytes),
                           slab.begin() + ptrdiff_t(rowStart + (i + 1) * outBytes),
                           slab.begin() + ptrdiff_t(rowStart + j * outBytes));
    sink(slab);
  }
}

std::vector<std::byte> extractLevelBytes(const BrickSource& source, uint32_t level,
                                         const LevelRegion& region) {
  std::vector<std::byte> all;
  extractLevel(
      source, level,
      [&](std::span<const std::byte> piece) { all.insert(all.end(), piece.begin(), piece.end()); }, region);
  return all;
}

double voxelValue(const BrickSource& source, uint32_t level, glm::u32vec3 voxel) {
  return VoxelReader(source).value(level, voxel);
}

NodeKey VoxelReader::nodeOf(uint32_t level, glm::u32vec3& voxel) const {
  const BrickSourceInfo& info = source_.info();
  const glm::u32vec3 levelDims = levelDimsOf(source_, level);
  if (!(voxel.x < levelDims.x && voxel.y < levelDims.y && voxel.z < levelDims.z))
    throw UsageError("extract: voxel " + formatDims(voxel) + " lies outside level " + std::to_string(level) +
                     " (" + formatDims(levelDims) + ")");
  voxel.x = fileVoxelX(info, voxel.x, levelDims.x);  // the store's index
  return NodeKey{info.layout.maxDepth - level, voxel / info.layout.brickSize};
}

bool VoxelReader::holds(uint32_t level, glm::u32vec3 voxel) const {
  try {
    return cached_ == nodeOf(level, voxel);
  } catch (const UsageError&) {
    return false;
  }
}

double VoxelReader::value(uint32_t level, glm::u32vec3 voxel) {
  const BrickSourceInfo& info = source_.info();
  const NodeKey node = nodeOf(level, voxel);
  const uint32_t b = info.layout.brickSize, edge = info.layout.storedBrickEdge();
  if (cached_ != node) {
    brick_.resize(source_.brickBytes());
    cached_.reset();  // a read that throws leaves no brick
    source_.readBrick(node, brick_);
    cached_ = node;
  }
  const glm::u32vec3 in = voxel - node.coord * b + kBrickBorder;
  const size_t index = (size_t(in.z) * edge + in.y) * edge + in.x;
  std::byte original[8];
  writeOriginal(storedTexel(brick_, info.storedType, index), info.volume.type, info.mapping, original);
  double value = 0.0;
  forSampleType(info.volume.type, [&](auto sample) {
    std::memcpy(&sample, original, sizeof(sample));
    value = double(sample);
  });
  return value;
}

void extractLevelToFile(const BrickSource& source, uint32_t level, const std::filesystem::path& output,
                        const LevelRegion& region, std::string_view header) {
  TemporaryFile file(output, "extract");
  file.writeAt(0, std::as_bytes(std::span(header.data(), header.size())));
  uint64_t offset = header.size();
  extractLevel(
      source, level,
      [&](std::span<const std::byte> piece) {
        file.writeAt(offset, piece);
        offset += piece.size();
      },
      region);
  file.commit();
}

namespace {

// Every digit a double needs to read back the same.
std::string exactNumber(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", v);
  return text;
}

std::string vectorText(glm::dvec3 v) {
  return "(" + exactNumber(v.x) + "," + exactNumber(v.y) + "," + exactNumber(v.z) + ")";
}

std::string nrrdTypeName(SampleType type) {
  switch (type) {
    case SampleType::Int8:
      return "int8";
    case SampleType::UInt8:
      return "uint8";
    case SampleType::Int16:
      return "int16";
    case SampleType::UInt16:
      return "uint16";
    case SampleType::Int32:
      return "int32";
    case SampleType::UInt32:
      return "uint32";
    case SampleType::Float32:
      return "float";
    case SampleType::Float64:
      return "double";
  }
  return "?";
}

}  // namespace

namespace {

// Where a region of a level lies (docs/RENDERING.md "Spaces"): its size, spacing, the file's axes, and its
// first sample's center, in the file's frame where the store keeps the file's origin (fileFrameOffset), else
// in the world. Throws UsageError for a region that is empty or leaves the level.
struct RegionPlacement {
  glm::u32vec3 size{0};
  glm::dvec3 spacing{1.0};
  AxisDirections directions{1.0};
  glm::dvec3 origin{0.0};
};

RegionPlacement placementOf(const BrickSource& source, uint32_t level, const LevelRegion& region) {
  const VolumeInfo& volume = source.info().volume;
  const glm::u32vec3 dims = levelDimsOf(source, level);
  const glm::u32vec3 end = glm::min(region.end, dims);
  if (!(region.begin.x < end.x && region.begin.y < end.y && region.begin.z < end.z))
    throw UsageError("extract: the region is empty or leaves level " + std::to_string(level));
  RegionPlacement p;
  p.size = end - region.begin;
  // Level L's sample i sits at (i + 0.5) 2^L s in the volume's own axes, turned about the extent's center.
  p.spacing = volume.spacing * std::ldexp(1.0, int(level));
  const glm::dvec3 center = 0.5 * volume.worldMax();
  // The first sample written: the file's index along x, which a store that keeps x reversed holds at the
  // other end, and whose x then points the file's way.
  glm::dvec3 firstIndex(region.begin);
  p.directions = volume.axes;
  if (source.info().xReversed) {
    firstIndex.x = double(fileVoxelX(source.info(), region.begin.x, dims.x));
    p.directions[0] = -volume.axes[0];
  }
  const glm::dvec3 first = (firstIndex + 0.5) * p.spacing;
  p.origin = center + volume.axes * (first - center) + fileFrameOffset(volume);
  return p;
}

// The source's description for a header's comment: one line, control bytes as '?'.
std::string describedOneLine(const VolumeInfo& volume) {
  std::string described = volume.description;
  for (char& c : described) c = (c >= ' ' && c != 127) || (c & 0x80) ? c : '?';
  return described;
}

template <typename T>
void putLittleEndian(std::string& bytes, size_t offset, T value) {
  static_assert(std::endian::native == std::endian::little, "NIfTI headers are written in native order");
  std::memcpy(bytes.data() + offset, &value, sizeof value);
}

}  // namespace

std::string nrrdHeaderOf(const BrickSource& source, uint32_t level, const LevelRegion& region) {
  const VolumeInfo& volume = source.info().volume;
  const RegionPlacement p = placementOf(source, level, region);
  std::string text = "NRRD0004\n# ropecast extract: level " + std::to_string(level) + " of " +
                     describedOneLine(volume) + "\n";
  text +=
      "type: " + nrrdTypeName(volume.type) +
      "\ndimension: 3\nspace: left-posterior-superior\nsizes: " + std::to_string(p.size.x) + " " +
      std::to_string(p.size.y) + " " + std::to_string(p.size.z) +
      "\nspace directions: " + vectorText(p.directions[0] * p.spacing.x) + " " +
      vectorText(p.directions[1] * p.spacing.y) + " " + vectorText(p.directions[2] * p.spacing.z) +
      "\nkinds: domain domain domain\nendian: little\nencoding: raw\nspace origin: " + vectorText(p.origin) +
      "\n\n";
  return text;
}

std::string niftiHeaderOf(const BrickSource& source, uint32_t level, const LevelRegion& region) {
  const VolumeInfo& volume = source.info().volume;
  const RegionPlacement p = placementOf(source, level, region);
  std::string bytes(kNiftiHeaderBytes, '\0');
  putLittleEndian<int32_t>(bytes, 0, 348);  // sizeof_hdr
  // dim: 3 axes of the region's size, the other four of one sample.
  putLittleEndian<int16_t>(bytes, 40, 3);
  for (size_t i = 4; i < 8; ++i) putLittleEndian<int16_t>(bytes, 40 + 2 * i, 1);
  for (int axis = 0; axis < 3; ++axis) {
    if (p.size[axis] > uint32_t(INT16_MAX))
      throw UsageError("extract: a NIfTI-1 file holds at most 32767 samples per axis; the region has " +
                       std::to_string(p.size[axis]) + " along " + "xyz"[axis] + " (write .nrrd or .raw)");
    putLittleEndian<int16_t>(bytes, 42 + 2 * size_t(axis), int16_t(p.size[axis]));
  }
  putLittleEndian<int16_t>(bytes, 70, niftiDatatypeOf(volume.type));
  putLittleEndian<int16_t>(bytes, 72, int16_t(8 * bytesPerSample(volume.type)));  // bitpix
  putLittleEndian<float>(bytes, 76, 1.0f);  // pixdim[0], qfac: unused without a qform
  for (int axis = 0; axis < 3; ++axis)
    putLittleEndian<float>(bytes, 80 + 4 * size_t(axis), float(p.spacing[axis]));
  putLittleEndian<float>(bytes, 108, float(kNiftiHeaderBytes));  // vox_offset: the samples follow
  bytes[123] = 2;                                                // xyzt_units: millimeters
  const std::string descrip =
      "ropecast extract: level " + std::to_string(level) + " of " + describedOneLine(volume);
  std::memcpy(bytes.data() + 148, descrip.data(), std::min<size_t>(descrip.size(), 79));
  // The sform (code 1, scanner anatomical): its columns the axes times the spacing and its last column the
  // first sample, in NIfTI's RAS (LPS with x and y negated). It places a mirroring file's samples as well.
  putLittleEndian<int16_t>(bytes, 254, 1);
  const glm::dvec3 toRas(-1.0, -1.0, 1.0);
  for (int row = 0; row < 3; ++row) {
    for (int axis = 0; axis < 3; ++axis)
      putLittleEndian<float>(bytes, 280 + 16 * size_t(row) + 4 * size_t(axis),
                             float(toRas[row] * p.directions[axis][row] * p.spacing[axis]));
    putLittleEndian<float>(bytes, 280 + 16 * size_t(row) + 12, float(toRas[row] * p.origin[row]));
  }
  std::memcpy(bytes.data() + 344, "n+1", 4);  // and 4 bytes of extension flags, zero: no extensions
  return bytes;
}

}  // namespace ropecast
