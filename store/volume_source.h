// VolumeSource: a scalar volume read slab by slab, the input of the converter (raw, NRRD, MetaImage, NIfTI,
// VTK (.vti, .vtk), image stacks, DICOM, HDF5, Zarr, N5, procedural). Sources never hold the whole volume;
// procedural ones generate what is asked for.
//
// Threads: info() any thread. readSlab() may be called from one thread at a time per source object
// (the converter reads slabs sequentially; a source may use worker threads internally).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <glm/vec3.hpp>

#include "core/error.h"
#include "core/orientation.h"
#include "core/sample_type.h"

namespace ropecast {

struct VolumeInfo {
  glm::u32vec3 dims{0};     // samples per axis
  glm::dvec3 spacing{1.0};  // world units per sample (mm for medical data)
  SampleType type = SampleType::UInt8;
  std::optional<double> valueMin;  // known value range in data units, if the source knows it cheaply
  std::optional<double>
      valueMax;  // (mapsOverValueRange types without it get a range pre-pass in the converter)
  // Where the index axes point in the world (core/orientation.h); the identity where the file says nothing.
  // Sources give what their file says, a mirroring frame included; a store's never mirrors (the converter
  // stores such a volume's x axis reversed).
  AxisDirections axes{1.0};
  // Where the file places the center of sample (0, 0, 0), in the frame `axes` point in (LPS for medical
  // inputs: the scanner's coordinates), in world units; absent where the file says nothing (raw volumes,
  // image stacks, procedural ones). A store's is that of its own sample (0, 0, 0): the converter moves it
  // with a crop and with an x axis it keeps reversed.
  std::optional<glm::dvec3> origin;
  // Whether `axes` point in a patient's frame (LPS): the file names an anatomical space (a DICOM series
  // placed by its positions, a NIfTI file's qform or sform, a NRRD's right-anterior-superior and the like, a
  // MetaImage's AnatomicalOrientation) and its axes were applied. The default view then faces the patient.
  bool patientFrame = false;
  // Of a file of several volumes (store/picked_volume.h): how many time points and channels it holds, and
  // which of each this volume is; 1, 1 and 0, 0 for a file of one volume.
  uint64_t timePoints = 1, channels = 1;
  uint32_t timePoint = 0, channel = 0;
  std::vector<std::string> channelNames;  // each channel's, where the file names them all; else empty
  std::string description;  // e.g. "raw:/data/bonsai_256x256x256_uint8.raw", "procedural:sphere:256"
  // What the source noticed about its input that a person should hear, though the samples are read as
  // described (the converter prints them as warnings): a NRRD's turned axes, gaps in a slice numbering.
  std::vector<std::string> notes;

  uint64_t sampleCount() const { return uint64_t(dims.x) * dims.y * dims.z; }
  size_t sliceBytes() const { return size_t(dims.x) * dims.y * bytesPerSample(type); }
  // The far corner of the volume's world box [0, n s].
  glm::dvec3 worldMax() const { return glm::dvec3(dims) * spacing; }
};

// A camera or a clip plane given in the world, seen from the volume's own axes (core/orientation.h): what
// every renderer draws, at its entry, so that a turned volume is drawn turned.
inline Camera cameraInVolume(const Camera& world, const VolumeInfo& v) {
  return cameraInVolume(world, v.axes, 0.5 * v.worldMax());
}
inline ClipPlane clipPlaneInVolume(const ClipPlane& world, const VolumeInfo& v) {
  return clipPlaneInVolume(world, v.axes, 0.5 * v.worldMax());
}
// The plane --mode slice shows where none is given, for this volume (core/orientation.h).
inline ClipPlane defaultSlicePlane(const RenderParams& params, const VolumeInfo& v) {
  return defaultSlicePlane(params, v.dims, v.spacing, v.axes);
}

// The file's frame (where `origin` places the samples) less the renderers' world, which turns the volume
// about its extent's center and puts sample i at (i + 0.5) s: the two differ by this translation, zero
// without an origin. A point of the world plus it is the point the file's frame names. For a store's volume
// (BrickSourceInfo::volume: its axes a turn, its origin its own first sample's).
glm::dvec3 fileFrameOffset(const VolumeInfo& v);

// Where the volume's origin places its last sample along x (origin + axes x (n - 1) s): the other end's
// origin of a volume whose x is read reversed (a store that keeps x reversed, and its file). Needs an origin.
inline glm::dvec3 originAtLastX(const VolumeInfo& v) {
  return *v.origin + v.axes[0] * (v.spacing.x * (v.dims.x - 1));
}

// The most samples a store holds per axis: keeps every node count far from overflow.
inline constexpr uint32_t kMaxDimsPerAxis = 1u << 20;

// Dims a store can hold: 1 to kMaxDimsPerAxis per axis.
inline bool isValidDims(glm::u32vec3 d) {
  for (int a = 0; a < 3; ++a)
    if (d[a] == 0 || d[a] > kMaxDimsPerAxis) return false;
  return true;
}

// The spacings a volume may have: the world box [0, n s] must exist (zero or negative spacings leave no box
// for rays to enter), and distances across it, squared, must stay finite in single precision.
inline constexpr double kMinSpacing = 1e-12, kMaxSpacing = 1e12;

inline bool isValidSpacing(glm::dvec3 s) {
  for (int a = 0; a < 3; ++a)
    if (!(s[a] >= kMinSpacing && s[a] <= kMaxSpacing)) return false;  // also refuses NaN
  return true;
}

// What isValidSpacing accepts, for messages.
inline std::string validSpacingText() {
  return "three numbers in [" + formatNumber(kMinSpacing) + ", " + formatNumber(kMaxSpacing) + "]";
}

// A volume's sizes as a header writes them ("X Y Z": NRRD's sizes, MetaImage's DimSize), read: three whole
// numbers from 1 to 2^32 - 1 whose samples, at 8 bytes (the widest), stay within 2^62 bytes. On failure
// `problem` says why, quoting the text, and `sizes` is 0.
struct SizesText {
  glm::u32vec3 sizes{0};
  std::string problem;
};
SizesText parseSizesText(std::string_view text);

// The warning a source gives when its file's `transform` ("its TransformMatrix") does not keep the axes at
// right angles: it is not applied.
std::string unappliedTransformNote(const std::string& path, const std::string& transform);

// "XxYxZ", for messages.
inline std::string formatDims(glm::u32vec3 d) {
  return std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z);
}

// "SX,SY,SZ" as the command line takes it, for messages.
inline std::string formatSpacing(glm::dvec3 s) {
  return formatNumber(s.x) + "," + formatNumber(s.y) + "," + formatNumber(s.z);
}

class VolumeSource {
 public:
  virtual ~VolumeSource() = default;
  virtual const VolumeInfo& info() const = 0;

  // Reads slices [z0, z0 + count) into `out` (count * info().sliceBytes() bytes), x fastest, samples in
  // info().type, native (little-endian) byte order. Throws ropecast::Error naming the source if the slices
  // leave the volume or `out` has another size, and naming the file on failure (truncated file,
  // unreadable slice, ...).
  void readSlab(uint32_t z0, uint32_t count, std::span<std::byte> out);

 protected:
  // readSlab once its arguments are checked: z0 + count <= info().dims.z and
  // out.size() == count * info().sliceBytes().
  virtual void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) = 0;
};

// The byte order of a raw file's samples.
enum class ByteOrder : uint8_t { Little, Big };

// Options that apply to sources whose file does not say them (raw files), or override what it says. All but
// the spacing, the time point and the channel are raw files' only: given for another input, opening it is a
// UsageError naming them.
struct SourceOptions {
  std::optional<glm::u32vec3> dims;     // --dims X,Y,Z
  std::optional<SampleType> type;       // --type T
  std::optional<glm::dvec3> spacing;    // --spacing SX,SY,SZ
  std::optional<ByteOrder> byteOrder;   // --byte-order little|big (default little)
  std::optional<uint64_t> headerBytes;  // --header-bytes N: bytes before the samples (default 0)
  // --time T, --channel C: which of a file's volumes to read (store/picked_volume.h); default the first.
  std::optional<uint32_t> timePoint;
  std::optional<uint32_t> channel;
  // --axes: an HDF5 dataset's, a Zarr array's or an N5 dataset's axes named, slowest first, one of t, c, z,
  // y, x each (store/array_axes.h), for an array that does not name them itself; empty: not given.
  std::string axes;
};

// Opens a source from a command-line spec:
//   path/to/name_XxYxZ_type.raw or any raw file with options.dims/type (and byteOrder, headerBytes),
//   path.nrrd / path.nhdr, path.mha / path.mhd, path.nii / path.nii.gz / a .hdr and .img pair, path.vti,
//   path.vtk, a directory or glob of 2D slices (TIFF/PNG), a multi-page TIFF, a folder of a DICOM series or
//   one of its images, an HDF5 file or FILE:/DATASET of one, a Zarr array or OME-Zarr image's folder, an N5
//   dataset's or multiscale group's folder, procedural:NAME:SIZE  (sphere, menger, noise, marschner-lobb).
// Throws ropecast::Error naming the spec and what was expected.
std::unique_ptr<VolumeSource> openVolumeSource(const std::string& spec, const SourceOptions& options = {});

// Whether openVolumeSource reads `spec` as a glob pattern of slices: it names no existing file and holds one
// of glob(3)'s metacharacters (*, ? or [); a file whose name holds them is that file.
bool isSlicePattern(const std::string& spec);

}  // namespace ropecast
