// libFuzzer target for the TIFF directory walk (store/tiff_directories.h): any file must either give a page
// count (0 or more) and layouts whose image data lies within the file, or none (not a TIFF), or throw
// ropecast::Error; never crash, hang or throw anything else. tiffPageCount reads a path, so each input is
// written to one temporary file first.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>

#include "core/error.h"
#include "fuzz/fuzz_input_file.h"
#include "store/tiff_directories.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = ropecast::fuzz::writeInputFile("pages.tif", data, size);
  try {
    const auto pages = ropecast::tiffPageLayouts(path);
    // A page's strips (or tiles) lie within the file: the source reads uncompressed ones at their offsets.
    if (pages)
      for (const ropecast::TiffPageLayout& page : *pages)
        for (size_t i = 0; i < std::min(page.dataOffsets.size(), page.dataByteCounts.size()); ++i)
          if (page.dataByteCounts[i] > 0 &&
              (page.dataOffsets[i] > size || page.dataByteCounts[i] > size - page.dataOffsets[i]))
            std::abort();
  } catch (const ropecast::Error&) {
    // A file cut short, or directories that loop, is expected to be refused this way.
  }
  return 0;
}
