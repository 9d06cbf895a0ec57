// The directories (pages) of a TIFF file, walked without decoding anything: how many pages there are, how
// each stores its pixels, and whether each directory and the image data it points to lie inside the file.
// OpenImageIO takes a file cut short for one with fewer pages, and reads image data past the end as zeros
// without failing; this walk tells a cut file from a whole one. Classic and BigTIFF, either byte order. Plain
// file reads, no OpenImageIO.
//
// Threads: any; no shared state.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

namespace ropecast {

// What a page's directory says of how its pixels are stored, as written: pages that agree on it are read
// alike (a stack's pages are checked against its first one by these, without decoding them).
struct TiffPageLayout {
  uint64_t width = 0, height = 0;
  uint64_t bitsPerSample = 1, samplesPerPixel = 1, sampleFormat = 1;  // the first sample's, TIFF's defaults
  uint64_t photometric = ~uint64_t(0), extraSamples = 0, planarConfiguration = 1;
  uint64_t compression = 1;              // 1: none
  uint64_t rowsPerStrip = ~uint32_t(0);  // TIFF's default: one strip
  bool tiled = false;                    // tiles, not strips
  bool bigEndian = false;                // the file's byte order
  // Non-zero (the page's number plus 1) where a layout tag is not a list of one unsigned value repeated: the
  // page is then like no other, and read to be checked.
  uint64_t unlikeOthers = 0;
  // Where the page's directory starts: not part of the layout (not compared).
  uint64_t directoryOffset = 0;

  bool operator==(const TiffPageLayout& o) const {
    return std::tie(width, height, bitsPerSample, samplesPerPixel, sampleFormat, photometric, extraSamples,
                    planarConfiguration, compression, rowsPerStrip, tiled, bigEndian, unlikeOthers) ==
           std::tie(o.width, o.height, o.bitsPerSample, o.samplesPerPixel, o.sampleFormat, o.photometric,
                    o.extraSamples, o.planarConfiguration, o.compression, o.rowsPerStrip, o.tiled,
                    o.bigEndian, o.unlikeOthers);
  }
};

// Each page's layout, in page order (none when its header points to no directory), or nullopt when `path`
// does not start with a TIFF header. Throws as tiffPageCount does.
std::optional<std::vector<TiffPageLayout>> tiffPageLayouts(const std::string& path);

// The number of pages of a TIFF file (0 when its header points to no directory), or nullopt when `path` does
// not start with a TIFF header. Throws ropecast::Error naming the file and page when a directory or the image
// data of a page lies past the end of the file, or when the directories loop. The caller has checked that
// `path` is a regular file.
std::optional<int> tiffPageCount(const std::string& path);

}  // namespace ropecast
