// Stands in for source_images.cpp in builds without OpenImageIO (ROPECAST_WITH_OIIO=OFF): image stacks and
// TIFFs are refused with a message that says why.
#include <algorithm>

#include "core/error.h"
#include "store/source_images.h"

namespace ropecast {

namespace {
[[noreturn]] void refuse(const std::string& what) {
  throw Error(what +
              ": image stacks and TIFF need OpenImageIO, and this ropecast was built without it "
              "(ROPECAST_WITH_OIIO=OFF)");
}
}  // namespace

bool sliceNameLess(std::string_view a, std::string_view b) {
  return std::lexicographical_compare(a.begin(), a.end(), b.begin(), b.end());
}

std::vector<std::string> listSliceFiles(const std::string& directoryOrPattern) {
  refuse(directoryOrPattern);
}

int countImagePages(const std::string& path) {
  refuse(path);
}

std::unique_ptr<VolumeSource> openImageStackSource(const std::string& directoryOrPattern,
                                                   const SourceOptions&) {
  refuse(directoryOrPattern);
}

std::unique_ptr<VolumeSource> openMultiPageTiffSource(const std::string& path, const SourceOptions&) {
  refuse(path);
}

}  // namespace ropecast
