#include "store/tiff_directories.h"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <set>
#include <vector>

#include "core/error.h"

namespace ropecast {
namespace {

// The tags that locate a page's image data: strips, or tiles.
constexpr uint16_t kStripOffsets = 273, kStripByteCounts = 279, kTileOffsets = 324, kTileByteCounts = 325;

class TiffFile {
 public:
  explicit TiffFile(const std::string& path) : path_(path), in_(path, std::ios::binary) {
    if (!in_) throw Error("cannot read image " + path + ": " + std::strerror(errno));
    in_.seekg(0, std::ios::end);
    size_ = uint64_t(in_.tellg());
  }

  const std::string& path() const { return path_; }
  uint64_t size() const { return size_; }
  bool holds(uint64_t at, uint64_t bytes) const { return at <= size_ && bytes <= size_ - at; }

  // `bytes` bytes from `at`, which holds() allows.
  std::vector<uint8_t> read(uint64_t at, uint64_t bytes) {
    std::vector<uint8_t> out(bytes);
    in_.seekg(std::streamoff(at));
    if (!in_.read(reinterpret_cast<char*>(out.data()), std::streamsize(bytes)))
      throw Error("cannot read image " + path_ + ": a read at byte " + std::to_string(at) + " failed");
    return out;
  }

  // An unsigned integer of `bytes` bytes in the file's byte order.
  uint64_t value(const uint8_t* p, int bytes) const {
    uint64_t v = 0;
    for (int i = 0; i < bytes; ++i) v |= uint64_t(p[bigEndian ? bytes - 1 - i : i]) << (8 * i);
    return v;
  }

  bool bigEndian = false;
  bool bigTiff = false;  // 64-bit offsets
  int offsetBytes() const { return bigTiff ? 8 : 4; }

 private:
  std::string path_;
  std::ifstream in_;
  uint64_t size_ = 0;
};

[[noreturn]] void cutShort(const TiffFile& file, int page, const std::string& what) {
  throw Error("TIFF file " + file.path() + " (page " + std::to_string(page) + ") is cut short: " + what +
              ", past the end of the file (" + std::to_string(file.size()) + " bytes)");
}

// The values of one directory entry whose type is an unsigned integer (SHORT, LONG, LONG8), held in the
// entry when they fit, else at the offset it holds; empty for other types.
std::vector<uint64_t> entryValues(TiffFile& file, const uint8_t* entry, int page) {
  const int type = int(file.value(entry + 2, 2));
  const int size = type == 3 ? 2 : type == 4 ? 4 : type == 16 ? 8 : 0;
  if (size == 0) return {};
  const uint64_t count = file.value(entry + 4, file.offsetBytes());
  const uint8_t* field = entry + 4 + file.offsetBytes();
  std::vector<uint8_t> stored;
  if (count > uint64_t(file.offsetBytes() / size)) {
    const uint64_t at = file.value(field, file.offsetBytes());
    if (count > file.size() / size || !file.holds(at, count * size))
      cutShort(file, page,
               "its table of " + std::to_string(count) + " strip or tile values at byte " +
                   std::to_string(at) + " runs on");
    stored = file.read(at, count * size);
    field = stored.data();
  }
  std::vector<uint64_t> values(count);
  for (uint64_t i = 0; i < count; ++i) values[i] = file.value(field + i * size, size);
  return values;
}

// The tags of a page's layout.
constexpr uint16_t kImageWidth = 256, kImageLength = 257, kBitsPerSample = 258, kCompression = 259,
                   kPhotometric = 262, kSamplesPerPixel = 277, kRowsPerStrip = 278,
                   kPlanarConfiguration = 284, kExtraSamples = 338, kSampleFormat = 339;

// Checks that the image data a directory points to lies inside the file; returns the page's layout.
TiffPageLayout checkImageData(TiffFile& file, const std::vector<uint8_t>& table, uint64_t entries, int page,
                              uint64_t directoryOffset) {
  const int entryBytes = file.bigTiff ? 20 : 12;
  std::vector<uint64_t> offsets, byteCounts;
  TiffPageLayout layout;
  for (uint64_t e = 0; e < entries; ++e) {
    const uint8_t* entry = table.data() + e * entryBytes;
    const auto tag = uint16_t(file.value(entry, 2));
    if (tag == kStripOffsets || tag == kTileOffsets) offsets = entryValues(file, entry, page);
    if (tag == kStripByteCounts || tag == kTileByteCounts) byteCounts = entryValues(file, entry, page);
    if (tag == kTileOffsets) layout.tiled = true;
    uint64_t* const field = tag == kImageWidth            ? &layout.width
                            : tag == kImageLength         ? &layout.height
                            : tag == kBitsPerSample       ? &layout.bitsPerSample
                            : tag == kSamplesPerPixel     ? &layout.samplesPerPixel
                            : tag == kSampleFormat        ? &layout.sampleFormat
                            : tag == kPhotometric         ? &layout.photometric
                            : tag == kExtraSamples        ? &layout.extraSamples
                            : tag == kPlanarConfiguration ? &layout.planarConfiguration
                            : tag == kCompression         ? &layout.compression
                            : tag == kRowsPerStrip        ? &layout.rowsPerStrip
                                                          : nullptr;
    if (field) {
      // A list (BitsPerSample and SampleFormat give one value per sample): its first value, and its others
      // when they differ from it, which makes the page unlike any other.
      const std::vector<uint64_t> values = entryValues(file, entry, page);
      const bool uniform =
          !values.empty() && std::ranges::count(values, values.front()) == long(values.size());
      *field = values.empty() ? 0 : values.front();
      if (!uniform) layout.unlikeOthers = uint64_t(page) + 1;
    }
  }
  uint64_t end = 0;
  for (size_t i = 0; i < std::min(offsets.size(), byteCounts.size()); ++i)
    if (byteCounts[i] > 0) end = std::max(end, offsets[i] + std::min(byteCounts[i], ~offsets[i]));
  if (end > file.size()) cutShort(file, page, "its image data runs to byte " + std::to_string(end));
  layout.bigEndian = file.bigEndian;
  layout.directoryOffset = directoryOffset;
  return layout;
}

}  // namespace

std::optional<int> tiffPageCount(const std::string& path) {
  const std::optional<std::vector<TiffPageLayout>> pages = tiffPageLayouts(path);
  if (!pages) return std::nullopt;
  return int(pages->size());
}

std::optional<std::vector<TiffPageLayout>> tiffPageLayouts(const std::string& path) {
  TiffFile file(path);
  if (!file.holds(0, 8)) return std::nullopt;
  const std::vector<uint8_t> header = file.read(0, 8);
  if (header[0] == 'M' && header[1] == 'M')
    file.bigEndian = true;
  else if (header[0] != 'I' || header[1] != 'I')
    return std::nullopt;
  const uint64_t magic = file.value(&header[2], 2);
  uint64_t at = 0;  // the first directory
  if (magic == 42) {
    at = file.value(&header[4], 4);
  } else if (magic == 43 && file.value(&header[4], 2) == 8 && file.holds(0, 16)) {
    file.bigTiff = true;
    at = file.value(file.read(8, 8).data(), 8);
  } else {
    return std::nullopt;
  }
  const int countBytes = file.bigTiff ? 8 : 2, entryBytes = file.bigTiff ? 20 : 12;
  std::set<uint64_t> seen;
  std::vector<TiffPageLayout> layouts;
  for (int pages = 0; at != 0; ++pages) {
    if (!seen.insert(at).second)
      throw Error("TIFF file " + path + " (page " + std::to_string(pages) +
                  "): its directory is an earlier page's; the directories loop");
    if (!file.holds(at, countBytes))
      cutShort(file, pages, "its directory starts at byte " + std::to_string(at));
    const uint64_t entries = file.value(file.read(at, countBytes).data(), countBytes);
    const uint64_t tableBytes = std::min(entries, file.size()) * entryBytes + file.offsetBytes();
    if (!file.holds(at + countBytes, tableBytes))
      cutShort(file, pages,
               "its directory runs from byte " + std::to_string(at) + " to byte " +
                   std::to_string(at + countBytes + tableBytes));
    const std::vector<uint8_t> table = file.read(at + countBytes, tableBytes);
    layouts.push_back(checkImageData(file, table, entries, pages, at));
    at = file.value(table.data() + entries * entryBytes, file.offsetBytes());
  }
  return layouts;
}

}  // namespace ropecast
