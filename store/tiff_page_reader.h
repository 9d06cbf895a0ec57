// Reads the samples of a multi-page TIFF's pages through libtiff, each page reached at its directory's offset
// (TiffPageLayout::directoryOffset), in time independent of the pages before it: OpenImageIO's TIFF reader
// (through Debian 12's libtiff) reaches page n by walking the n directories before it. Pages of one sample a
// pixel in whole bytes, in strips or tiles, compressed in any way this libtiff decodes; the samples come as
// stored, in the machine's byte order, in rows of the page's width.
//
// Part of the image module (libtiff is loaded with OpenImageIO; tools/image_module.h).
// Threads: one thread at a time per reader.
#pragma once

#include <cstddef>
#include <memory>
#include <span>
#include <string>

#include "store/tiff_directories.h"

namespace ropecast {

class TiffPageReader {
 public:
  // Opens `path` (a TIFF: tiffPageLayouts gave its pages); throws ropecast::Error naming it.
  explicit TiffPageReader(std::string path);
  ~TiffPageReader();
  TiffPageReader(const TiffPageReader&) = delete;
  TiffPageReader& operator=(const TiffPageReader&) = delete;

  // Whether read() reads pages of `layout`: one sample a pixel of 8, 16, 32 or 64 bits, stored as a page that
  // agrees with the others (not unlikeOthers), compressed in a way this libtiff decodes.
  static bool reads(const TiffPageLayout& layout);

  // Page `page` of the file, whose layout reads() allows, into `out` (width x height samples of
  // bitsPerSample / 8 bytes). Throws ropecast::Error naming the file and page, with libtiff's message, when
  // its directory or data cannot be read or decoded, or no longer says what `layout` does.
  void read(const TiffPageLayout& layout, int page, std::span<std::byte> out);

 private:
  struct Open;
  std::string path_;
  std::unique_ptr<Open> open_;
};

}  // namespace ropecast
