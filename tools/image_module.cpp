// The image module's entry point (tools/image_module.h): the one symbol ropecast_images.so exports.
#include "tools/image_module.h"

#include "store/source_dicom.h"
#include "store/source_hdf5.h"
#include "store/source_images.h"

namespace {

const ropecast::tools::ImageModule kModule{
    .encodeImage = &ropecast::encodeImage,
    .imageWriterProblem = &ropecast::imageWriterProblem,
    .decodeImage = &ropecast::decodeImage,
    .countImagePages = &ropecast::countImagePages,
    .openImageStackSource = &ropecast::openImageStackSource,
    .openMultiPageTiffSource = &ropecast::openMultiPageTiffSource,
    .openDicomSource = &ropecast::openDicomSource,
    .openHdf5Source = &ropecast::openHdf5Source,
};

}  // namespace

extern "C" __attribute__((visibility("default"))) const ropecast::tools::ImageModule*
ropecast_image_module() {
  return &kModule;
}
