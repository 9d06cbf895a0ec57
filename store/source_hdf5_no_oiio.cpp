// Stands in for source_hdf5.cpp in builds without the image module (ROPECAST_WITH_OIIO=OFF): HDF5 files are
// refused with a message that says why.
#include "core/error.h"
#include "store/source_hdf5.h"

namespace ropecast {

std::unique_ptr<VolumeSource> openHdf5Source(const std::string& spec, const SourceOptions&) {
  throw Error(spec +
              ": HDF5 files are read in ropecast's image module, and this ropecast was built without it "
              "(ROPECAST_WITH_OIIO=OFF)");
}

}  // namespace ropecast
