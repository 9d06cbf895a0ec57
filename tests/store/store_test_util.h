// Helpers shared by the store, converter and VolumeSource tests: synthetic volumes, a direct (non-streaming)
// computation of the level pyramid and of expected bricks, a temporary directory, typed slab reads, raw
// file bytes (plain and gzip-compressed), writing them and the message a bad source spec gives. Test code
// only; one thread.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>
#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "core/error.h"
#include "store/array_source.h"
#include "store/octree_layout.h"
#include "store/volume_source.h"

namespace ropecast::testing {

// `data` deflated at `level` as one gzip member (else a zlib stream).
inline std::string deflatedOf(const std::string& data, int level, bool gzip) {
  z_stream zs{};
  EXPECT_EQ(deflateInit2(&zs, level, Z_DEFLATED, gzip ? 15 + 16 : 15, 8, Z_DEFAULT_STRATEGY), Z_OK);
  std::string out(deflateBound(&zs, uLong(data.size())) + 64, '\0');
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
  zs.avail_in = uInt(data.size());
  zs.next_out = reinterpret_cast<Bytef*>(out.data());
  zs.avail_out = uInt(out.size());
  EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
  out.resize(zs.total_out);
  deflateEnd(&zs);
  return out;
}

// `data` as one gzip member, as NRRD's gzip encoding and .nii.gz files hold it.
inline std::string gzipOf(const std::string& data) {
  return deflatedOf(data, 6, true);
}

// `values` as a file holds them: after `header` bytes, in the given byte order.
template <typename T>
std::string fileBytes(const std::vector<T>& values, bool bigEndian = false, size_t header = 0) {
  std::string bytes(header + values.size() * sizeof(T), 'h');
  std::memcpy(bytes.data() + header, values.data(), values.size() * sizeof(T));
  if (bigEndian != (std::endian::native == std::endian::big))
    for (size_t i = header; i < bytes.size(); i += sizeof(T))
      std::reverse(bytes.begin() + i, bytes.begin() + i + sizeof(T));
  return bytes;
}

// Writes `size` bytes at `data` to `path`, replacing it. Throws ropecast::Error naming the file if it cannot.
inline void writeFile(const std::filesystem::path& path, const void* data, size_t size) {
  std::ofstream out(path, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
  if (!out.good()) throw Error("test: cannot write " + path.string());
}
inline void writeFile(const std::filesystem::path& path, std::string_view bytes) {
  writeFile(path, bytes.data(), bytes.size());
}
inline void writeFile(const std::filesystem::path& path, const std::vector<char>& bytes) {
  writeFile(path, bytes.data(), bytes.size());
}

// A fresh directory under the system temp dir, removed with everything in it at the end of the test.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "ropecast-store-XXXXXX").string();
    path_ = mkdtemp(pattern.data());
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  std::string file(const std::string& name) const { return (path_ / name).string(); }
  size_t fileCount() const {
    return size_t(
        std::distance(std::filesystem::directory_iterator(path_), std::filesystem::directory_iterator()));
  }

 private:
  std::filesystem::path path_;
};

// `count` samples of T, x fastest: a value per sample that differs between neighbors in every axis and uses
// the type's full width.
template <typename T>
std::vector<T> samplePattern(size_t count) {
  std::vector<T> v(count);
  for (size_t i = 0; i < v.size(); ++i) {
    if constexpr (std::is_floating_point_v<T>)
      v[i] = T(double(i) * 0.37 - 1000.0);
    else
      v[i] = T(i * 2654435761u >> 7);
  }
  return v;
}
template <typename T>
std::vector<T> samplePattern(glm::u32vec3 dims) {
  return samplePattern<T>(size_t(dims.x) * dims.y * dims.z);
}

// Slices [z0, z0 + count) of a source whose samples are T.
template <typename T>
std::vector<T> readSlab(VolumeSource& source, uint32_t z0, uint32_t count) {
  std::vector<T> slab(size_t(count) * source.info().sliceBytes() / sizeof(T));
  source.readSlab(z0, count, std::as_writable_bytes(std::span(slab)));
  return slab;
}

// What a file-format test expects a source to say of the volume it wrote.
struct ExpectedVolume {
  glm::u32vec3 dims;
  SampleType type;
  glm::dvec3 spacing;
  std::string description;
};

// That `source` is the volume `expected` describes, without notes, holding `values`: read whole, and from a
// middle slice on.
template <typename T>
void expectVolume(VolumeSource& source, const ExpectedVolume& expected, const std::vector<T>& values) {
  const VolumeInfo& info = source.info();
  EXPECT_EQ(info.dims, expected.dims) << expected.description;
  EXPECT_EQ(info.type, expected.type) << expected.description;
  EXPECT_EQ(info.spacing, expected.spacing) << expected.description;
  EXPECT_EQ(info.description, expected.description);
  EXPECT_TRUE(info.notes.empty()) << expected.description;
  EXPECT_EQ(readSlab<T>(source, 0, info.dims.z), values) << expected.description;
  const uint32_t middle = info.dims.z / 2;
  const auto slab = readSlab<T>(source, middle, info.dims.z - middle);
  EXPECT_TRUE(std::equal(slab.begin(), slab.end(), values.begin() + middle * info.sliceBytes() / sizeof(T)))
      << expected.description;
}

// A header a parser must refuse: what the case is, the header's text, and words its message must hold.
struct RefusedHeader {
  std::string what, header, expected;
};

// Each case's header, given to `parse(header, fileName)`, throws ropecast::Error whose message names
// `fileName` and holds the case's expected words.
template <typename Parse>
void expectHeadersRefused(const std::vector<RefusedHeader>& cases, const std::string& fileName, Parse parse) {
  for (const RefusedHeader& c : cases) {
    try {
      parse(c.header, fileName);
      ADD_FAILURE() << c.what << ": parsed without error";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(fileName), std::string::npos) << c.what << ": " << message;
      EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
    }
  }
}

// The message opening `spec` fails with, or "" when it opens.
inline std::string errorOf(const std::string& spec, const SourceOptions& options = {}) {
  try {
    openVolumeSource(spec, options);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// A smooth ball with noise inside and exact zeros outside (so some bricks are constant), in [0, 1].
inline std::vector<double> ballField(glm::u32vec3 d, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-0.05, 0.05);
  std::vector<double> v(size_t(d.x) * d.y * d.z);
  const glm::dvec3 c = glm::dvec3(d) * 0.5;
  const double radius = 0.45 * std::min({d.x, d.y, d.z}) + 2.0;
  for (uint32_t z = 0; z < d.z; ++z)
    for (uint32_t y = 0; y < d.y; ++y)
      for (uint32_t x = 0; x < d.x; ++x) {
        const double r =
            glm::length((glm::dvec3(x, y, z) + 0.5 - c) / glm::dvec3(d) * double(std::min({d.x, d.y, d.z})));
        const double n = noise(rng);
        v[(size_t(z) * d.y + y) * d.x + x] =
            r < radius ? std::clamp(1.0 - r / radius + n + 0.05, 0.0, 1.0) : 0.0;
      }
  return v;
}

template <typename T>
std::vector<T> toType(const std::vector<double>& field, double lo, double hi) {
  std::vector<T> out(field.size());
  for (size_t i = 0; i < field.size(); ++i) out[i] = T(std::lround(lo + field[i] * (hi - lo)));
  return out;
}

inline VolumeInfo volumeInfo(glm::u32vec3 dims, SampleType type) {
  VolumeInfo info;
  info.dims = dims;
  info.type = type;
  info.spacing = {0.5, 0.75, 1.25};
  info.description = "test volume";
  return info;
}

// Levels 0..maxLevel of stored values, each the rounded 2x2x2 mean of the previous (odd edges repeat).
inline std::vector<std::vector<uint16_t>> levelPyramid(std::vector<uint16_t> level0,
                                                       const OctreeLayout& layout) {
  std::vector<std::vector<uint16_t>> levels{std::move(level0)};
  for (uint32_t l = 1; l <= layout.maxDepth; ++l) {
    const glm::u32vec3 f = layout.levelDims(l - 1), c = layout.levelDims(l);
    const auto& fine = levels.back();
    std::vector<uint16_t> coarse(size_t(c.x) * c.y * c.z);
    for (uint32_t z = 0; z < c.z; ++z)
      for (uint32_t y = 0; y < c.y; ++y)
        for (uint32_t x = 0; x < c.x; ++x) {
          uint32_t sum = 0;
          for (uint32_t o = 0; o < 8; ++o) {
            const uint32_t fx = std::min(2 * x + (o & 1), f.x - 1),
                           fy = std::min(2 * y + ((o >> 1) & 1), f.y - 1),
                           fz = std::min(2 * z + (o >> 2), f.z - 1);
            sum += fine[(size_t(fz) * f.y + fy) * f.x + fx];
          }
          coarse[(size_t(z) * c.y + y) * c.x + x] = uint16_t((sum + 4) / 8);
        }
    levels.push_back(std::move(coarse));
  }
  return levels;
}

// The brick of `key` computed directly: its samples with borders, clamped to the level's edge.
inline std::vector<uint16_t> expectedBrick(const std::vector<std::vector<uint16_t>>& levels,
                                           const OctreeLayout& layout, const NodeKey& key) {
  const uint32_t level = layout.levelOfDepth(key.depth), edge = layout.storedBrickEdge(),
                 b = layout.brickSize;
  const glm::u32vec3 d = layout.levelDims(level);
  std::vector<uint16_t> brick(layout.storedBrickSamples());
  for (uint32_t k = 0; k < edge; ++k)
    for (uint32_t j = 0; j < edge; ++j)
      for (uint32_t i = 0; i < edge; ++i) {
        const auto at = [&](uint32_t c, uint32_t o, uint32_t n) {
          return uint32_t(std::clamp<int64_t>(int64_t(c) * b + o - int64_t(kBrickBorder), 0, int64_t(n) - 1));
        };
        brick[(size_t(k) * edge + j) * edge + i] =
            levels[level][(size_t(at(key.coord.z, k, d.z)) * d.y + at(key.coord.y, j, d.y)) * d.x +
                          at(key.coord.x, i, d.x)];
      }
  return brick;
}

// Stored values of level 0 for a source of integer type (uint8/uint16 as is, int16 offset by 32768).
template <typename T>
std::vector<uint16_t> storedValues(const std::vector<T>& samples) {
  std::vector<uint16_t> out(samples.size());
  for (size_t i = 0; i < samples.size(); ++i)
    out[i] = std::is_same_v<T, int16_t> ? uint16_t(int32_t(samples[i]) + 32768) : uint16_t(samples[i]);
  return out;
}

inline std::vector<uint16_t> widen(std::span<const std::byte> bytes, SampleType stored) {
  std::vector<uint16_t> out;
  if (stored == SampleType::UInt8) {
    for (std::byte b : bytes) out.push_back(uint16_t(b));
  } else {
    out.resize(bytes.size() / 2);
    std::memcpy(out.data(), bytes.data(), bytes.size());
  }
  return out;
}

}  // namespace ropecast::testing
