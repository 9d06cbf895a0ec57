// openVolumeSource: chooses the VolumeSource for a command-line spec (see store/volume_source.h):
//   "procedural:" prefix -> procedural; .nrrd/.nhdr -> NRRD; .mha/.mhd -> MetaImage;
//   .nii/.nii.gz/.hdr/.hdr.gz, or an .img(.gz) beside a .hdr(.gz) -> NIfTI; .vtk -> legacy VTK; .vti -> VTK
//   image data; a pattern with * or ? -> image stack; a directory -> Zarr if it holds Zarr metadata, else N5
//   if it holds attributes.json, else a DICOM series if it holds DICOM files, or
//   no slices and DICOM files in its subfolders, else image stack; a DICOM file -> its series; .tif/.tiff ->
//   multi-page TIFF (a single page alone is an error); an HDF5 file (.h5, .hdf5, .ims, ... or its signature),
//   alone or as FILE:/DATASET -> HDF5; a BigDataViewer XML -> HDF5 or N5, as its image loader says (its
//   dataset's one view); a single .png or
//   a store is an error; anything else -> raw.
#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "store/bdv_xml.h"
#include "store/hdf5_spec.h"
#include "store/picked_volume.h"
#include "store/source_dicom.h"
#include "store/source_hdf5.h"
#include "store/source_images.h"
#include "store/source_metaimage.h"
#include "store/source_n5.h"
#include "store/source_nifti.h"
#include "store/source_nrrd.h"
#include "store/source_procedural.h"
#include "store/source_raw.h"
#include "store/source_vti.h"
#include "store/source_vtk.h"
#include "store/source_zarr.h"
#include "store/store.h"
#include "store/volume_source.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

// Only raw files lack dims, type, byte order and the offset of their samples; every other source says its own
// (a procedural volume, an image stack), or has no such layout. `kind` names the source in the message.
void rejectRawOptions(const std::string& spec, const SourceOptions& options, const std::string& kind) {
  std::vector<std::string> given;
  if (options.dims) given.push_back("--dims");
  if (options.type) given.push_back("--type");
  if (options.byteOrder) given.push_back("--byte-order");
  if (options.headerBytes) given.push_back("--header-bytes");
  if (given.empty()) return;
  std::string names = given.front();
  for (size_t i = 1; i < given.size(); ++i) names += (i + 1 == given.size() ? " and " : ", ") + given[i];
  throw UsageError("openVolumeSource: " + spec + ": " + names + (given.size() == 1 ? " applies" : " apply") +
                   " to raw files only; " + kind + " states its own dimensions, type and layout");
}

// Sources of one volume: `--time` and `--channel` can only pick its first (0), and are refused past it.
void requireSingleVolume(const std::string& spec, const SourceOptions& options) {
  pickVolume(options, VolumeCounts{}, spec);
}

// Whether a folder holds image slices: a DICOM folder with them too is ambiguous.
bool holdsSliceImages(const std::string& directory) {
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(directory, ec))
    if (isSliceImageName(entry.path().string())) return true;
  return false;
}

}  // namespace

bool isSlicePattern(const std::string& spec) {
  std::error_code ec;
  return spec.find_first_of("*?[") != std::string::npos && !fs::exists(spec, ec);
}

std::unique_ptr<VolumeSource> openVolumeSource(const std::string& spec, const SourceOptions& options) {
  if (!options.axes.empty() && !hdf5SpecOf(spec) && !isZarrFolder(spec) && !isN5Folder(spec))
    throw UsageError("openVolumeSource: " + spec +
                     ": --axes applies to HDF5 datasets, Zarr arrays and N5 datasets only (other files state "
                     "their axes)");
  if (isProceduralSpec(spec)) {
    rejectRawOptions(spec, options, "a procedural volume");
    requireSingleVolume(spec, options);
    return openProceduralSource(proceduralNameAndSize(spec), options);
  }
  if (isSlicePattern(spec)) {
    rejectRawOptions(spec, options, "a stack of image slices");
    requireSingleVolume(spec, options);
    return openImageStackSource(spec, options);
  }
  if (hdf5SpecOf(spec)) {
    rejectRawOptions(spec, options, "an HDF5 dataset");
    return openHdf5Source(spec, options);
  }
  std::error_code ec;
  const fs::file_status status = fs::status(spec, ec);
  if (!fs::exists(status)) throw Error(spec + ": no such file or directory");
  if (fs::is_directory(status)) {
    if (isZarrFolder(spec)) {
      rejectRawOptions(spec, options, "a Zarr array");
      return openZarrSource(spec, options);
    }
    if (isN5Folder(spec)) {
      rejectRawOptions(spec, options, "an N5 dataset");
      return openN5Source(spec, options);
    }
    if (!listDicomFiles(spec).empty()) {
      if (holdsSliceImages(spec))
        throw Error(
            "openVolumeSource: " + spec +
            " holds DICOM files and image slices (.png, .tif); give one DICOM image to read its series, "
            "or a pattern (e.g. " +
            (fs::path(spec) / "*.png").string() + ") to read the slices");
      rejectRawOptions(spec, options, "a DICOM series");
      return openDicomSource(spec, options);
    }
    if (!holdsSliceImages(spec) && !listDicomFilesBelow(spec).empty()) {
      rejectRawOptions(spec, options, "a DICOM series");
      return openDicomSource(spec, options);  // a disc's or an export's folders, without a DICOMDIR
    }
    rejectRawOptions(spec, options, "a stack of image slices");
    requireSingleVolume(spec, options);
    return openImageStackSource(spec, options);
  }
  // A FIFO or a device would block or never end the reads below (their magic numbers first).
  requireRegularFile(spec, "openVolumeSource: " + spec);
  if (startsWithDicomMagic(spec)) {
    rejectRawOptions(spec, options, "a DICOM series");
    return openDicomSource(spec, options);
  }
  const std::string ext = lowerExtension(spec);
  if (ext == ".nrrd" || ext == ".nhdr") {
    rejectRawOptions(spec, options, "a NRRD header");
    return openNrrdSource(spec, options);
  }
  if (ext == ".mha" || ext == ".mhd") {
    rejectRawOptions(spec, options, "a MetaImage header");
    return openMetaImageSource(spec, options);
  }
  if (hasNiftiName(spec) || !niftiPairHeader(spec).empty()) {
    rejectRawOptions(spec, options, "a NIfTI header");
    return openNiftiSource(spec, options);
  }
  if (ext == ".vti") {
    rejectRawOptions(spec, options, "a VTK image data file");
    return openVtiSource(spec, options);
  }
  if (ext == ".xml") {
    if (!isBdvXml(spec))
      throw Error("openVolumeSource: " + spec +
                  " is XML but no BigDataViewer dataset (no SpimData element); of XML files, BigDataViewer's "
                  "(beside its HDF5 file) and VTK image data (.vti) are read");
    rejectRawOptions(spec, options, "a BigDataViewer dataset");
    const BdvDataset dataset = parseBdvXml(readTextInput(spec, "BigDataViewer XML " + spec), spec);
    if (dataset.format == BdvImageFormat::N5) return openBdvN5Source(spec, dataset, options);
    return openHdf5Source(spec, options);
  }
  if (ext == ".vtk") {
    rejectRawOptions(spec, options, "a legacy VTK file");
    requireSingleVolume(spec, options);
    return openVtkSource(spec, options);
  }
  if (ext == ".tif" || ext == ".tiff") {
    rejectRawOptions(spec, options, "a TIFF");
    return openMultiPageTiffSource(spec, options);  // a single page is refused there
  }
  if (ext == ".dcm")
    throw Error("openVolumeSource: " + spec +
                " is not a DICOM file of the standard's file format (no DICM signature after its 128-byte "
                "preamble)");
  if (ext == ".png")
    throw Error(
        "openVolumeSource: " + spec +
        " is a single image; give its folder or a pattern (e.g. dir/slice_*.png) to read a stack of slices");
  if (isStoreFile(spec))  // else read as a raw file of unknown dimensions
    throw Error(
        "openVolumeSource: " + spec +
        " is a ropecast store already (convert reads volumes: raw, NRRD, MetaImage, NIfTI, VTK (.vtk, "
        ".vti), image stacks, TIFF, DICOM, HDF5, Zarr); render, view "
        "and info read it as it is, and `ropecast extract` writes a level of it as a raw volume");
  requireSingleVolume(spec, options);
  return openRawSource(spec, options);
}

}  // namespace ropecast
