#include "store/tiff_page_reader.h"

#include <tiffio.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <vector>

#include "core/error.h"

namespace ropecast {

struct TiffPageReader::Open {
  TIFF* tiff = nullptr;
  std::string lastError;  // libtiff's last error message for this file
  ~Open() {
    if (tiff) TIFFClose(tiff);
  }
};

namespace {

// libtiff's messages for one file: its errors kept for the exception that follows, its warnings (of the
// private tags ImageJ and microscopes write, say) dropped. Both handled here, so the process-wide handlers
// (OpenImageIO's) are not called.
int keepError(TIFF*, void* lastError, const char*, const char* format, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, format, args);
  *static_cast<std::string*>(lastError) = text;
  return 1;
}

int dropWarning(TIFF*, void*, const char*, const char*, va_list) {
  return 1;
}

}  // namespace

TiffPageReader::TiffPageReader(std::string path) : path_(std::move(path)), open_(std::make_unique<Open>()) {
  TIFFOpenOptions* options = TIFFOpenOptionsAlloc();
  TIFFOpenOptionsSetErrorHandlerExtR(options, keepError, &open_->lastError);
  TIFFOpenOptionsSetWarningHandlerExtR(options, dropWarning, nullptr);
  // Not memory-mapped ("m"): a file cut while it is open then fails a read, where a mapping would kill the
  // process with SIGBUS.
  open_->tiff = TIFFOpenExt(path_.c_str(), "rm", options);
  TIFFOpenOptionsFree(options);
  if (!open_->tiff) throw Error("cannot read image " + path_ + ": " + open_->lastError);
}

TiffPageReader::~TiffPageReader() = default;

bool TiffPageReader::reads(const TiffPageLayout& layout) {
  const uint64_t bits = layout.bitsPerSample;
  return layout.unlikeOthers == 0 && layout.samplesPerPixel == 1 && layout.extraSamples == 0 &&
         (bits == 8 || bits == 16 || bits == 32 || bits == 64) && layout.compression <= UINT16_MAX &&
         TIFFIsCODECConfigured(uint16_t(layout.compression));
}

void TiffPageReader::read(const TiffPageLayout& layout, int page, std::span<std::byte> out) {
  TIFF* const tiff = open_->tiff;
  const auto fail = [&](const std::string& what) {
    throw Error("cannot read image slice " + path_ + " (page " + std::to_string(page) +
                "): " + (open_->lastError.empty() ? what : open_->lastError));
  };
  open_->lastError.clear();
  if (!TIFFSetSubDirectory(tiff, layout.directoryOffset)) fail("its directory cannot be read");
  uint32_t width = 0, height = 0;
  uint16_t bits = 0, samples = 0;
  TIFFGetField(tiff, TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tiff, TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted(tiff, TIFFTAG_BITSPERSAMPLE, &bits);
  TIFFGetFieldDefaulted(tiff, TIFFTAG_SAMPLESPERPIXEL, &samples);
  const size_t sampleBytes = bits / 8, rowBytes = size_t(width) * sampleBytes;
  // The file may have changed since its directories were walked.
  if (width != layout.width || height != layout.height || bits != layout.bitsPerSample || samples != 1 ||
      out.size() != rowBytes * height)
    fail("its directory no longer says what it did when the file was opened");

  if (TIFFIsTiled(tiff)) {
    uint32_t tileWidth = 0, tileHeight = 0;
    TIFFGetField(tiff, TIFFTAG_TILEWIDTH, &tileWidth);
    TIFFGetField(tiff, TIFFTAG_TILELENGTH, &tileHeight);
    const size_t tileRowBytes = size_t(tileWidth) * sampleBytes;
    constexpr size_t kMaxTileBytes = size_t(1) << 30;
    if (tileWidth == 0 || tileHeight == 0 || tileRowBytes > kMaxTileBytes / tileHeight)
      fail("its tiles of " + std::to_string(tileWidth) + " x " + std::to_string(tileHeight) +
           " samples are empty or larger than 1 GiB");
    std::vector<std::byte> tile(tileRowBytes * tileHeight);
    for (uint32_t y = 0; y < height; y += tileHeight)
      for (uint32_t x = 0; x < width; x += tileWidth) {
        if (TIFFReadEncodedTile(tiff, TIFFComputeTile(tiff, x, y, 0, 0), tile.data(), tmsize_t(tile.size())) <
            0)
          fail("the tile at (" + std::to_string(x) + ", " + std::to_string(y) + ") cannot be decoded");
        const uint32_t rows = std::min(tileHeight, height - y), columns = std::min(tileWidth, width - x);
        for (uint32_t r = 0; r < rows; ++r)
          std::memcpy(out.data() + (y + r) * rowBytes + x * sampleBytes, tile.data() + r * tileRowBytes,
                      columns * sampleBytes);
      }
    return;
  }
  uint32_t rowsPerStrip = 0;
  TIFFGetFieldDefaulted(tiff, TIFFTAG_ROWSPERSTRIP, &rowsPerStrip);
  rowsPerStrip = std::clamp<uint32_t>(rowsPerStrip, 1, std::max<uint32_t>(height, 1));
  for (uint32_t strip = 0, row = 0; row < height; ++strip, row += rowsPerStrip) {
    const size_t bytes = std::min(rowsPerStrip, height - row) * rowBytes;
    if (TIFFReadEncodedStrip(tiff, strip, out.data() + row * rowBytes, tmsize_t(bytes)) != tmsize_t(bytes))
      fail("strip " + std::to_string(strip) + " cannot be decoded");
  }
}

}  // namespace ropecast
