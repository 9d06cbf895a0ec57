#include "store/source_nifti.h"

#include <zlib.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "core/input_file.h"
#include "store/file_samples.h"
#include "store/picked_volume.h"
#include "store/placed_stack.h"
#include "store/source_raw.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

bool endsWith(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() && text.substr(text.size() - suffix.size()) == suffix;
}

std::string lowerFileName(const std::string& path) {
  return lowerAscii(fs::path(path).filename().string());
}

// `path` with the `from` part of its name's ending (".hdr" in ".hdr.gz", say) replaced by `to`, in the case
// the name has it in; tried with and without ".gz" after it.
std::string siblingWithExtension(const std::string& path, std::string_view from, std::string_view to) {
  const std::string lower = lowerFileName(path);
  const size_t gz = endsWith(lower, ".gz") ? 3 : 0;
  const std::string name = fs::path(path).filename().string();
  const size_t at = name.size() - gz - from.size();
  const bool upper = name[at + 1] >= 'A' && name[at + 1] <= 'Z';
  std::string ext(to);
  if (upper)
    for (char& c : ext) c = char(std::toupper(static_cast<unsigned char>(c)));
  const std::string stem = (fs::path(path).parent_path() / name.substr(0, at)).string();
  std::error_code ec;
  for (const std::string& candidate : {stem + ext, stem + ext + (upper ? ".GZ" : ".gz")})
    if (fs::is_regular_file(candidate, ec)) return candidate;
  return "";
}

bool startsWithGzipMagic(const PosixFile& file) {
  std::array<std::byte, 2> magic{};
  return file.readSomeAt(0, magic) == 2 && magic[0] == std::byte(0x1f) && magic[1] == std::byte(0x8b);
}

// The type that holds slope * v + intercept for every v of `stored` (exactly where the values stay whole).
SampleType scaledType(SampleType stored, double slope, double intercept) {
  if (stored == SampleType::Float64) return SampleType::Float64;
  if (stored == SampleType::Float32 || slope != std::floor(slope) || intercept != std::floor(intercept))
    return SampleType::Float32;
  double lo = 0.0, hi = 0.0;
  forSampleType(stored, [&](auto zero) {
    using T = decltype(zero);
    const double a = double(std::numeric_limits<T>::lowest()) * slope + intercept;
    const double b = double(std::numeric_limits<T>::max()) * slope + intercept;
    lo = std::min(a, b);
    hi = std::max(a, b);
  });
  return integerTypeHolding(lo, hi, bytesPerSample(stored) == 1);
}

// A NIfTI volume whose values are scaled: slabs read as stored, then scaled into the source's type.
class ScaledNiftiSource final : public VolumeSource {
 public:
  ScaledNiftiSource(VolumeInfo info, std::unique_ptr<FileSamples> samples, const NiftiHeader& header)
      : info_(std::move(info)), samples_(std::move(samples)), header_(header) {}

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const uint64_t storedSlice = uint64_t(info_.dims.x) * info_.dims.y * bytesPerSample(header_.type);
    stored_.resize(size_t(count * storedSlice));
    samples_->read(z0 * storedSlice, stored_);
    samplesToNative(stored_, header_.type, header_.bigEndian);
    const size_t n = size_t(uint64_t(count) * info_.dims.x * info_.dims.y);
    forSampleType(header_.type, [&](auto storedZero) {
      using S = decltype(storedZero);
      forSampleType(info_.type, [&](auto outZero) {
        using T = decltype(outZero);
        for (size_t i = 0; i < n; ++i) {
          S v;
          std::memcpy(&v, stored_.data() + i * sizeof(S), sizeof(S));
          const T scaled = T(double(v) * header_.slope + header_.intercept);
          std::memcpy(out.data() + i * sizeof(T), &scaled, sizeof(T));
        }
      });
    });
  }

  VolumeInfo info_;
  std::unique_ptr<FileSamples> samples_;
  NiftiHeader header_;
  std::vector<std::byte> stored_;  // a slab as stored, before scaling
};

}  // namespace

bool hasNiftiName(const std::string& path) {
  const std::string lower = lowerFileName(path);
  for (std::string_view ending : {".nii", ".nii.gz", ".hdr", ".hdr.gz"})
    if (endsWith(lower, ending)) return true;
  return false;
}

std::string niftiPairHeader(const std::string& imagePath) {
  const std::string lower = lowerFileName(imagePath);
  if (!endsWith(lower, ".img") && !endsWith(lower, ".img.gz")) return "";
  return siblingWithExtension(imagePath, ".img", ".hdr");
}

NiftiHeader readNiftiHeaderFile(const std::string& path) {
  requireRegularFile(path, "cannot read " + path);  // gzopen would wait on a FIFO
  gzFile file = gzopen(path.c_str(), "rb");         // reads a file that is not gzip-compressed as it is
  if (!file) throw Error("cannot open " + path + ": " + std::strerror(errno));
  std::array<std::byte, kNifti2HeaderBytes> bytes{};
  const int got = gzread(file, bytes.data(), unsigned(bytes.size()));
  int status = Z_OK;
  const std::string problem = got < 0 ? gzerror(file, &status) : "";
  gzclose(file);
  if (got < 0) throw Error("NIfTI file " + path + ": cannot read its header (" + problem + ")");
  const std::string lower = lowerFileName(path);
  const bool pairHeader = endsWith(lower, ".hdr") || endsWith(lower, ".hdr.gz");
  return parseNiftiHeader(std::span(bytes).first(size_t(got)), path, /*analyzeAllowed=*/pairHeader);
}

std::string niftiDataPath(const NiftiHeader& header, const std::string& headerPath) {
  if (!header.pairedFile) return headerPath;
  const std::string lower = lowerFileName(headerPath);
  if (!endsWith(lower, ".hdr") && !endsWith(lower, ".hdr.gz")) return "";
  return siblingWithExtension(headerPath, ".hdr", ".img");
}

std::unique_ptr<VolumeSource> openNiftiSource(const std::string& path, const SourceOptions& options) {
  std::string headerPath = path;
  const std::string lower = lowerFileName(path);
  if (endsWith(lower, ".img") || endsWith(lower, ".img.gz")) {
    headerPath = niftiPairHeader(path);
    if (headerPath.empty()) throw Error("NIfTI image " + path + ": no .hdr beside it holds its header");
  }
  const NiftiHeader header = readNiftiHeaderFile(headerPath);
  const std::string dataPath = niftiDataPath(header, headerPath);
  if (dataPath.empty())
    throw Error(
        "NIfTI header " + headerPath +
        " is the header of a header/image pair ('ni1' or 'ni2'), but no .img or .img.gz of its name lies "
        "beside it");
  const std::string kind = header.analyze      ? "ANALYZE image file"
                           : header.pairedFile ? "NIfTI image file"
                                               : "NIfTI file";
  const std::string file = kind + " " + dataPath;
  const PickedVolume picked = pickVolume(options, {header.timePoints, header.components}, file);
  // The picked volume's samples follow those of the volumes before it.
  const uint64_t volumeStart =
      header.voxOffset +
      (uint64_t(picked.channel) * header.timePoints + picked.timePoint) * header.dataBytes();
  auto data = std::make_unique<PosixFile>(dataPath);
  SampleBlock block;
  block.fileKind = kind;
  block.volume = formatDims(header.sizes) + " " + std::string(sampleTypeName(header.type));
  block.bytes = header.dataBytes();
  if (startsWithGzipMagic(*data)) {
    block.encoding = SampleEncoding::Deflated;
    block.skip = volumeStart;
  } else {
    block.start = volumeStart;
  }
  auto samples = std::make_unique<FileSamples>(std::move(data), std::move(block));

  VolumeInfo info;
  info.dims = header.sizes;
  info.type = header.type;
  info.spacing = options.spacing.value_or(header.spacing);
  info.description = (header.analyze ? "analyze:" : "nifti:") + path;
  if (header.analyze)
    info.notes.push_back(
        headerPath +
        " is an ANALYZE 7.5 header (no NIfTI magic): the volume is drawn in the file's axes, "
        "unoriented (programs read ANALYZE's orientation code differently, left and right "
        "above all)");
  describePicked(info, picked);
  info.axes = header.axes;
  info.origin = header.origin;
  // An sform whose third axis alone is off the slices' normal (a gantry's tilt kept in the file): the slices
  // are placed where they lie, in the patient's frame.
  std::optional<SliceGrid> grid;
  bool placed = false;
  if (header.shearedSform && !options.spacing) {
    const auto& s = *header.shearedSform;
    info.origin = s[3];
    placed = placeSkewedSlices(info, {s[0], s[1], s[2]}, "the slices of " + path, grid);
    if (!placed) info.origin.reset();
  }
  info.patientFrame = info.origin.has_value();  // a qform or sform applied: NIfTI's frame is a patient's
  if (header.transformNotApplied && !placed)
    info.notes.push_back(unappliedTransformNote(headerPath, "its qform or sform"));
  if (header.spacingUnknown && !options.spacing && !placed)
    info.notes.push_back(headerPath +
                         ": pixdim gives no spacing for some axis (zero or not a number); 1 is used there "
                         "(--spacing sets it)");
  const auto placedWhereTheyLie = [&grid](std::unique_ptr<VolumeSource> source) {
    return grid ? resampleSlices(std::move(source), std::move(*grid)) : std::move(source);
  };
  if (!header.scaled)
    return placedWhereTheyLie(openBlockSource(std::move(info), std::move(samples), header.bigEndian));

  info.type = scaledType(header.type, header.slope, header.intercept);
  if (info.type == SampleType::UInt8) {
    info.valueMin = 0.0;
    info.valueMax = 255.0;
  }
  info.description += " (values scaled by scl_slope " + formatNumber(header.slope) + " and scl_inter " +
                      formatNumber(header.intercept) + ")";
  return placedWhereTheyLie(std::make_unique<ScaledNiftiSource>(std::move(info), std::move(samples), header));
}

}  // namespace ropecast
