// libFuzzer target for the TIFF directory walk (store/tiff_directories.h) and the page reads at the
// directories it finds (store/tiff_page_reader.h): any file must either give a page count (0 or more) and
// layouts whose directories lie within the file, or none (not a TIFF), or throw ropecast::Error; each page
// the reader reads must be read or throw ropecast::Error; never crash, hang or throw anything else. Both read
// a path, so each input is written to one temporary file first.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "fuzz/fuzz_input_file.h"
#include "store/tiff_directories.h"
#include "store/tiff_page_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string& path = ropecast::fuzz::writeInputFile("pages.tif", data, size);
  try {
    const auto pages = ropecast::tiffPageLayouts(path);
    // A page's directory lies within the file: the source reaches pages by it.
    if (pages)
      for (const ropecast::TiffPageLayout& page : *pages)
        if (page.directoryOffset >= size) std::abort();
    if (!pages || pages->empty()) return 0;
    ropecast::TiffPageReader reader(path);
    std::vector<std::byte> samples;
    for (size_t p = 0; p < pages->size(); ++p) {
      const ropecast::TiffPageLayout& page = (*pages)[p];
      // Pages of at most a megabyte, so that each input takes little time.
      if (!ropecast::TiffPageReader::reads(page) || page.width > 4096 || page.height > 4096 ||
          page.width * page.height * (page.bitsPerSample / 8) > (1u << 20))
        continue;
      samples.resize(page.width * page.height * (page.bitsPerSample / 8));
      try {
        reader.read(page, int(p), samples);
      } catch (const ropecast::Error&) {
        // Data that does not decode, or a directory libtiff refuses, is expected to be refused this way.
      }
    }
  } catch (const ropecast::Error&) {
    // A file cut short, or directories that loop, is expected to be refused this way.
  }
  return 0;
}
