// The image module: the parts of ropecast that read or write image files through OpenImageIO (image codecs,
// image-stack sources), GDCM (DICOM series) and HDF5 files, built as a shared
// module, ropecast_images.so, that the ropecast executable loads the first time a command needs one.
// OpenImageIO loads a few hundred shared libraries, which took the larger part of every start; commands that
// touch no image but PNG (info, verify, convert from raw or NRRD, render to PNG, compare of PNGs: libpng,
// reference/png_codec.h; regress of PNG goldens) no longer load them (docs/BENCHMARKS.md, "Start-up"). Test
// executables link those parts directly.
//
// The module links its own copy of core/ and store/, so it keeps no state of ropecast's: it makes no
// TemporaryFile (whose removal on a signal lives in the executable's copy) and returns bytes and images for
// the executable to write. Its sources do not change when it is reached this way: the executable defines the
// functions of reference/image_codec.h, store/source_images.h, store/source_dicom.h and store/source_hdf5.h
// that it uses as calls into this table (tools/image_module_client.cpp).
//
// Threads: imageModule() from any thread (the first call loads the module).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/float_image.h"
#include "reference/image_codec.h"
#include "store/volume_source.h"

namespace ropecast::tools {

// The module's functions, with the signatures of the declarations they implement.
struct ImageModule {
  // This build's layout of the table: a module of another build is refused, not called.
  static constexpr uint32_t kLayout = 4;
  uint32_t layout = kLayout;
  uint32_t size = sizeof(ImageModule);

  std::vector<unsigned char> (*encodeImage)(const std::string& where, const std::string& path,
                                            const ImageEncoding& encoding, const void* pixels);
  std::string (*imageWriterProblem)(const std::string& path);
  FloatImage (*decodeImage)(const std::string& path);
  int (*countImagePages)(const std::string& path);
  std::unique_ptr<VolumeSource> (*openImageStackSource)(const std::string& directoryOrPattern,
                                                        const SourceOptions& options);
  std::unique_ptr<VolumeSource> (*openMultiPageTiffSource)(const std::string& path,
                                                           const SourceOptions& options);
  std::unique_ptr<VolumeSource> (*openDicomSource)(const std::string& spec, const SourceOptions& options);
  std::unique_ptr<VolumeSource> (*openHdf5Source)(const std::string& spec, const SourceOptions& options);
};

// The file name of the module, and the name of its one exported function, which returns its table.
inline constexpr const char* kImageModuleFile = "ropecast_images.so";
inline constexpr const char* kImageModuleEntry = "ropecast_image_module";

// The loaded module's table. The module is looked for next to the executable (a build tree) and in
// ROPECAST_IMAGE_MODULE_DIR relative to it (an installed tree), and stays loaded until the process ends.
// Throws ropecast::Error saying where it looked and why it could not load it.
const ImageModule& imageModule();

}  // namespace ropecast::tools
