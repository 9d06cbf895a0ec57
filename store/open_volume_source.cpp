// openVolumeSource: chooses the VolumeSource for a command-line spec (see store/volume_source.h):
//   "procedural:" prefix -> procedural; .nrrd/.nhdr -> NRRD; a directory or a pattern with * or ? -> image
//   stack; .tif/.tiff -> multi-page TIFF (a single page alone is an error); anything else -> raw.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

#include "core/error.h"
#include "store/source_images.h"
#include "store/source_nrrd.h"
#include "store/source_procedural.h"
#include "store/source_raw.h"
#include "store/volume_source.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

std::string lowerExtension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

// Only raw files lack dims and type; every other source says its own.
void rejectDimsAndType(const std::string& spec, const SourceOptions& options) {
  if (options.dims || options.type)
    throw UsageError(
        "openVolumeSource: " + spec +
        ": --dims and --type apply to raw files only; this source states its own dimensions and type");
}

}  // namespace

bool isSlicePattern(const std::string& spec) {
  std::error_code ec;
  return spec.find_first_of("*?[") != std::string::npos && !fs::exists(spec, ec);
}

std::unique_ptr<VolumeSource> openVolumeSource(const std::string& spec, const SourceOptions& options) {
  if (isProceduralSpec(spec)) {
    rejectDimsAndType(spec, options);
    return openProceduralSource(proceduralNameAndSize(spec), options);
  }
  if (isSlicePattern(spec)) {
    rejectDimsAndType(spec, options);
    return openImageStackSource(spec, options);
  }
  std::error_code ec;
  const fs::file_status status = fs::status(spec, ec);
  if (!fs::exists(status)) throw Error(spec + ": no such file or directory");
  if (fs::is_directory(status)) {
    rejectDimsAndType(spec, options);
    return openImageStackSource(spec, options);
  }
  const std::string ext = lowerExtension(spec);
  if (ext == ".nrrd" || ext == ".nhdr") {
    rejectDimsAndType(spec, options);
    return openNrrdSource(spec, options);
  }
  if (ext == ".tif" || ext == ".tiff") {
    rejectDimsAndType(spec, options);
    if (countImagePages(spec) < 2)
      throw Error(
          "openVolumeSource: " + spec +
          " is a single-page TIFF; give its folder or a pattern (e.g. dir/slice_*.tif) to read a stack of "
          "slices, or a multi-page TIFF");
    return openMultiPageTiffSource(spec, options);
  }
  return openRawSource(spec, options);
}

}  // namespace ropecast
