#include "tools/volume_read_options.h"

#include "core/error.h"
#include "store/array_axes.h"
#include "store/source_raw.h"
#include "tools/cli_checks.h"
#include "tools/cli_values.h"

namespace ropecast::tools {

namespace {

// --type: the names of parseSampleType (core/sample_type.h), aliases included.
std::vector<std::pair<std::string, SampleType>> sampleTypeNames() {
  std::vector<std::pair<std::string, SampleType>> names;
  for (const auto& [name, type] : kSampleTypeNames) names.emplace_back(name, type);
  return names;
}

}  // namespace

std::string VolumeReadArgs::firstGiven() const {
  if (!dims.empty()) return "--dims";
  if (type) return "--type";
  if (byteOrder) return "--byte-order";
  if (headerBytes) return "--header-bytes";
  if (!spacing.empty()) return "--spacing";
  if (timePoint) return "--time";
  if (channel) return "--channel";
  if (!axes.empty()) return "--axes";
  return "";
}

void addVolumeReadOptions(CLI::App& app, VolumeReadArgs& a) {
  addDimsOption(app, "--dims", a.dims, "X,Y,Z samples per axis of a raw file");
  addEnumOption(app, "--type", a.type, sampleTypeNames(), "sample type of a raw file", /*ignoreCase=*/true,
                "{int8,uint8,int16,uint16,int32,uint32,float32,float64} (or an alias: u8, short, int, float, "
                "double, ...)");
  addEnumOption(
      app, "--byte-order", a.byteOrder,
      std::vector<std::pair<std::string, ByteOrder>>{{"little", ByteOrder::Little}, {"big", ByteOrder::Big}},
      "byte order of a raw file's samples (default little)");
  app.add_option("--header-bytes", a.headerBytes, "bytes to skip at the start of a raw file (default 0)")
      ->type_name("N")
      ->transform(integerRange(0, double(kMaxRawHeaderBytes)));
  addTripleOption(app, "--spacing", a.spacing,
                  "SX,SY,SZ world units per sample (default 1,1,1 or the file's)");
  app.add_option(
         "--time", a.timePoint,
         "which time point of a time series to read, from 0 (NIfTI, NRRD, DICOM, TIFF hyperstacks, OME-Zarr, "
         "HDF5: Imaris, BigDataViewer, ilastik; an HDF5 dataset's, a Zarr array's or an N5 dataset's t axis "
         "of "
         "--axes; "
         "default "
         "0)")
      ->type_name("T")
      ->transform(integerRange(0, double(UINT32_MAX)));
  app.add_option(
         "--channel", a.channel,
         "which channel or component of several to read, from 0 (TIFF hyperstacks, OME-TIFF, OME-Zarr, "
         "MetaImage, HDF5: Imaris, ilastik, BigDataViewer view setups; a NIfTI's 5th dimension, a NRRD's or "
         "a .vti array's components; an HDF5 dataset's, a Zarr array's or an N5 dataset's c axis of --axes; "
         "default 0)")
      ->type_name("C")
      ->transform(integerRange(0, double(UINT32_MAX)));
  app.add_option(
         "--axes", a.axes,
         "an HDF5 dataset's, a Zarr array's or an N5 dataset's axes, slowest first, for one that does not "
         "name them: "
         "a letter per axis, t (time), c (channel), z, y or x (e.g. tzyx, czyx, tczyx)")
      ->type_name("LETTERS")
      ->check(notEmpty("axis letters"));
}

SourceOptions sourceOptionsOf(const VolumeReadArgs& a, const std::string& who) {
  SourceOptions options;
  if (!a.dims.empty()) options.dims = glm::u32vec3(a.dims.at(0), a.dims.at(1), a.dims.at(2));
  if (!a.spacing.empty()) {
    options.spacing = toVec3(a.spacing);
    if (!isValidSpacing(*options.spacing))
      throw UsageError(who + ": --spacing " + formatTriple(a.spacing) + ": expected " + validSpacingText());
  }
  options.type = a.type;
  options.byteOrder = a.byteOrder;
  options.headerBytes = a.headerBytes;
  options.timePoint = a.timePoint;
  options.channel = a.channel;
  if (!a.axes.empty()) {
    if (const GivenAxisNames given = axisNamesOf(a.axes); !given.problem.empty())
      throw UsageError(who + ": --axes " + a.axes + ": " + given.problem);
    options.axes = a.axes;
  }
  return options;
}

void refuseVolumeReadOptions(const VolumeReadArgs& a, const std::string& why) {
  if (const std::string given = a.firstGiven(); !given.empty())
    throw UsageError(given + " applies to a volume read from its file; " + why);
}

}  // namespace ropecast::tools
