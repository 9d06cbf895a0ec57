// Stands in for source_dicom.cpp in builds without the image module (ROPECAST_WITH_OIIO=OFF): DICOM series
// are refused with a message that says why.
#include "core/error.h"
#include "store/source_dicom.h"

namespace ropecast {

std::unique_ptr<VolumeSource> openDicomSource(const std::string& spec, const SourceOptions&) {
  throw Error(
      spec +
      ": DICOM series need GDCM, read in ropecast's image module, and this ropecast was built without "
      "it (ROPECAST_WITH_OIIO=OFF)");
}

}  // namespace ropecast
