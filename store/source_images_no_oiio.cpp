// Stands in for source_images.cpp in builds without OpenImageIO (ROPECAST_WITH_OIIO=OFF): image stacks and
// TIFFs are refused with a message that says why.
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
