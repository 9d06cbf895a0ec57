// The DICOM-series source (store/source_dicom.h): headers read with GDCM's Scanner, which stops before the
// pixel data, and each slice's pixels with its ImageReader, which decodes the compressed transfer syntaxes
// (JPEG, JPEG-LS, JPEG 2000, RLE).
#include "store/source_dicom.h"

#include <signal.h>
#include <unistd.h>

#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <gdcmPixelFormat.h>
#include <gdcmScanner.h>
#include <gdcmSequenceOfItems.h>
#include <gdcmTag.h>
#include <gdcmTrace.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/number_text.h"
#include "store/dicom_structure.h"
#include "store/picked_volume.h"
#include "store/placed_stack.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

const gdcm::Tag kSeriesUid(0x0020, 0x000e), kSeriesNumber(0x0020, 0x0011), kModality(0x0008, 0x0060),
    kSeriesDescription(0x0008, 0x103e), kInstanceNumber(0x0020, 0x0013), kPosition(0x0020, 0x0032),
    kOrientation(0x0020, 0x0037), kRows(0x0028, 0x0010), kColumns(0x0028, 0x0011),
    kPixelSpacing(0x0028, 0x0030), kFrames(0x0028, 0x0008), kSamplesPerPixel(0x0028, 0x0002),
    kPhotometric(0x0028, 0x0004), kBitsAllocated(0x0028, 0x0100), kBitsStored(0x0028, 0x0101),
    kPixelRepresentation(0x0028, 0x0103), kSlope(0x0028, 0x1053), kIntercept(0x0028, 0x1052),
    kSliceThickness(0x0018, 0x0050), kSpacingBetweenSlices(0x0018, 0x0088), kSopClass(0x0008, 0x0016),
    kTemporalPosition(0x0020, 0x0100), kAcquisitionNumber(0x0020, 0x0012);
// An enhanced image's functional groups: shared by all frames, per frame, and the two that place a frame.
const gdcm::Tag kSharedGroups(0x5200, 0x9229), kPerFrameGroups(0x5200, 0x9230),
    kPlanePosition(0x0020, 0x9113), kPlaneOrientation(0x0020, 0x9116), kPixelMeasures(0x0028, 0x9110);

// The SOP classes of enhanced (and legacy converted enhanced) CT, MR and PET images, whose per-frame
// functional groups place each frame: GDCM takes the spacing between frames from them.
constexpr const char* kEnhancedSopClasses[] = {
    "1.2.840.10008.5.1.4.1.1.2.1", "1.2.840.10008.5.1.4.1.1.2.2", "1.2.840.10008.5.1.4.1.1.4.1",
    "1.2.840.10008.5.1.4.1.1.4.4", "1.2.840.10008.5.1.4.1.1.130", "1.2.840.10008.5.1.4.1.1.128.1"};

// GDCM's own warnings and errors (an enhanced image's frames out of order, say), kept from stderr: this
// reader says what matters in its errors and notes, with GDCM's words where it cannot decode a file.
std::ostringstream& gdcmMessages() {
  static std::ostringstream messages;
  return messages;
}

void captureGdcmMessages() {
  gdcm::Trace::SetWarningStream(gdcmMessages());
  gdcm::Trace::SetErrorStream(gdcmMessages());
  gdcmMessages().str("");
}

// The last line GDCM wrote since captureGdcmMessages, as ": LINE" ("" when none).
std::string gdcmWords() {
  std::istringstream lines(gdcmMessages().str());
  std::string line, last;
  while (std::getline(lines, line))
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  return last.empty() ? "" : ": " + last;
}

// GDCM, as Debian builds it, asserts (aborts) on some damaged files that the structure check passes. While it
// reads one, an abort first says which file, then goes on to the handler that was there before (a command's,
// which removes its temporaries: core/temporary_file.h) and dies of it.
std::atomic<const char*> fileInGdcm{nullptr};
struct sigaction abortBeforeGdcm {};

void sayWhichFileGdcmStoppedOn(int) {
  if (const char* file = fileInGdcm.load()) {
    const auto say = [](const char* text) { [[maybe_unused]] auto n = ::write(2, text, std::strlen(text)); };
    say("ropecast: error: GDCM stopped on the DICOM file ");
    say(file);
    say(", which is damaged or of a form it cannot read\n");
  }
  ::sigaction(SIGABRT, &abortBeforeGdcm, nullptr);
  ::raise(SIGABRT);
}

// Names `file` (a path, or a folder being scanned) to an abort while it lives. One reading thread at a time.
class GdcmReading {
 public:
  explicit GdcmReading(const std::string& file) {
    static std::once_flag installed;
    std::call_once(installed, [] {
      struct sigaction action {};
      action.sa_handler = sayWhichFileGdcmStoppedOn;
      sigemptyset(&action.sa_mask);
      ::sigaction(SIGABRT, &action, &abortBeforeGdcm);
    });
    fileInGdcm.store(file.c_str());
  }
  ~GdcmReading() { fileInGdcm.store(nullptr); }
  GdcmReading(const GdcmReading&) = delete;
  GdcmReading& operator=(const GdcmReading&) = delete;
};

// `text` without DICOM's padding (spaces and NULs) at either end.
std::string withoutPadding(std::string text) {
  const auto padding = [](unsigned char c) { return c == ' ' || c == '\0'; };
  while (!text.empty() && padding(text.back())) text.pop_back();
  size_t start = 0;
  while (start < text.size() && padding(text[start])) ++start;
  return text.substr(start);
}

// A header value as text, trimmed of DICOM's padding; "" when the file does not have it.
std::string textOf(const gdcm::Scanner& scanner, const std::string& file, const gdcm::Tag& tag) {
  const char* value = scanner.GetValue(file.c_str(), tag);
  return withoutPadding(value ? value : "");
}

// The items of the sequence `tag` in `ds` (null when it has none): held, because GDCM may parse them anew.
gdcm::SmartPointer<gdcm::SequenceOfItems> itemsOf(const gdcm::DataSet& ds, const gdcm::Tag& tag) {
  if (!ds.FindDataElement(tag)) return nullptr;
  gdcm::SmartPointer<gdcm::SequenceOfItems> items = ds.GetDataElement(tag).GetValueAsSQ();
  return items && items->GetNumberOfItems() > 0 ? items : nullptr;
}

// The text of `tag` in the first item of the functional group `group` (Plane Position, say) of a frame's or
// the shared groups `groups`; "" when any of them is missing.
std::string groupText(const gdcm::DataSet& groups, const gdcm::Tag& group, const gdcm::Tag& tag) {
  const gdcm::SmartPointer<gdcm::SequenceOfItems> items = itemsOf(groups, group);
  if (!items) return "";
  const gdcm::DataSet& item = items->GetItem(1).GetNestedDataSet();
  if (!item.FindDataElement(tag)) return "";
  const gdcm::ByteValue* value = item.GetDataElement(tag).GetByteValue();
  return value ? withoutPadding(std::string(value->GetPointer(), value->GetLength())) : "";
}

// The numbers of a multi-valued header value ("a\b\c"); nullopt when it is missing, has another count, or a
// value is not a number.
std::optional<std::vector<double>> numbersOf(const std::string& text, size_t count) {
  if (text.empty()) return std::nullopt;
  std::vector<double> values;
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\\', start);
    if (end == std::string::npos) end = text.size();
    const std::optional<double> value =
        parseWholeNumber<double>(std::string_view(text).substr(start, end - start));
    if (!value || !std::isfinite(*value)) return std::nullopt;
    values.push_back(*value);
    start = end + 1;
  }
  if (values.size() != count) return std::nullopt;
  return values;
}

std::optional<double> numberOf(const std::string& text) {
  const auto values = numbersOf(text, 1);
  return values ? std::optional<double>(values->front()) : std::nullopt;
}

// What one image's header says about it.
struct DicomImage {
  std::string path;
  std::string seriesUid, seriesNumber, modality, seriesDescription;
  std::optional<glm::dvec3> position;
  std::optional<std::vector<double>> orientation;  // row direction, then column direction
  std::optional<double> instance;
  // What tells the images of one position apart in a series of several time points (or acquisitions).
  std::optional<double> temporalPosition, acquisition;
  double slope = 1.0, intercept = 0.0;
  // The pixel format, as text: images of one series must agree on it.
  std::string rows, columns, samplesPerPixel, photometric, bitsAllocated, bitsStored, pixelRepresentation;
  std::string frames, pixelSpacing, sliceThickness, spacingBetweenSlices, sopClass;
};

// The headers of the image files among `files` (those with rows and columns: a DICOMDIR or a report has
// none).
std::vector<DicomImage> scanImages(const std::vector<std::string>& files, const std::string& where) {
  if (files.empty()) return {};
  gdcm::Scanner scanner;
  for (const gdcm::Tag& tag : {kSeriesUid,      kSeriesNumber,     kModality,         kSeriesDescription,
                               kInstanceNumber, kPosition,         kOrientation,      kRows,
                               kColumns,        kPixelSpacing,     kFrames,           kSamplesPerPixel,
                               kPhotometric,    kBitsAllocated,    kBitsStored,       kPixelRepresentation,
                               kSlope,          kIntercept,        kSliceThickness,   kSpacingBetweenSlices,
                               kSopClass,       kTemporalPosition, kAcquisitionNumber})
    scanner.AddTag(tag);
  for (const std::string& file : files)
    if (const std::string problem = dicomStructureProblem(file); !problem.empty())
      throw Error("DICOM file " + file + " cannot be read: " + problem);
  captureGdcmMessages();
  const GdcmReading reading(where);
  if (!scanner.Scan(files)) throw Error("cannot read the DICOM headers in " + where + gdcmWords());
  std::vector<DicomImage> images;
  for (const std::string& file : files) {
    if (!scanner.IsKey(file.c_str())) continue;  // a file GDCM could not parse: not an image of the series
    DicomImage image;
    image.path = file;
    const auto text = [&](const gdcm::Tag& tag) { return textOf(scanner, file, tag); };
    image.rows = text(kRows);
    image.columns = text(kColumns);
    if (image.rows.empty() || image.columns.empty()) continue;
    image.seriesUid = text(kSeriesUid);
    image.seriesNumber = text(kSeriesNumber);
    image.modality = text(kModality);
    image.seriesDescription = text(kSeriesDescription);
    if (const auto p = numbersOf(text(kPosition), 3)) image.position = glm::dvec3((*p)[0], (*p)[1], (*p)[2]);
    image.orientation = numbersOf(text(kOrientation), 6);
    image.instance = numberOf(text(kInstanceNumber));
    image.temporalPosition = numberOf(text(kTemporalPosition));
    image.acquisition = numberOf(text(kAcquisitionNumber));
    const std::string slope = text(kSlope), intercept = text(kIntercept);
    if (!slope.empty()) {
      const auto value = numberOf(slope);
      if (!value || *value == 0.0)
        throw Error("DICOM image " + file + " has Rescale Slope '" + slope + "'; expected a non-zero number");
      image.slope = *value;
    }
    if (!intercept.empty()) {
      const auto value = numberOf(intercept);
      if (!value)
        throw Error("DICOM image " + file + " has Rescale Intercept '" + intercept + "'; expected a number");
      image.intercept = *value;
    }
    image.samplesPerPixel = text(kSamplesPerPixel);
    image.photometric = text(kPhotometric);
    image.bitsAllocated = text(kBitsAllocated);
    image.bitsStored = text(kBitsStored);
    image.pixelRepresentation = text(kPixelRepresentation);
    image.frames = text(kFrames);
    image.pixelSpacing = text(kPixelSpacing);
    image.sliceThickness = text(kSliceThickness);
    image.spacingBetweenSlices = text(kSpacingBetweenSlices);
    image.sopClass = text(kSopClass);
    images.push_back(std::move(image));
  }
  return images;
}

// "1.2.840.113619.2.55: series 3, CT 'ABDOMEN', 120 images, e.g. dir/IM0001", for the list of a folder's
// series.
std::string seriesSummary(const std::vector<const DicomImage*>& images) {
  const DicomImage& first = *images.front();
  std::string text = first.seriesUid.empty() ? std::string("(no Series Instance UID)") : first.seriesUid;
  text += ":";
  if (!first.seriesNumber.empty()) text += " series " + first.seriesNumber + ",";
  if (!first.modality.empty()) text += " " + first.modality;
  if (!first.seriesDescription.empty()) text += " '" + first.seriesDescription + "'";
  if (!first.modality.empty() || !first.seriesDescription.empty()) text += ",";
  return text + " " + std::to_string(images.size()) + (images.size() == 1 ? " image" : " images") +
         ", e.g. " + first.path;
}

// Throws naming both files where `image` differs from `first` in size or pixel format.
void checkSameFormat(const DicomImage& first, const DicomImage& image) {
  const struct {
    const char* name;
    const std::string DicomImage::*field;
  } fields[] = {{"Rows", &DicomImage::rows},
                {"Columns", &DicomImage::columns},
                {"Samples per Pixel", &DicomImage::samplesPerPixel},
                {"Photometric Interpretation", &DicomImage::photometric},
                {"Bits Allocated", &DicomImage::bitsAllocated},
                {"Bits Stored", &DicomImage::bitsStored},
                {"Pixel Representation", &DicomImage::pixelRepresentation}};
  for (const auto& f : fields)
    if (first.*f.field != image.*f.field)
      throw Error("DICOM image " + image.path + " has " + f.name + " " + image.*f.field + ", but " +
                  first.path + " has " + first.*f.field +
                  "; the images of a series must share one size and pixel format");
}

uint32_t positiveInteger(const DicomImage& image, const std::string& text, const char* name, uint32_t max) {
  const auto value = numberOf(text);
  if (!value || *value < 1 || *value > max || *value != std::floor(*value))
    throw Error("DICOM image " + image.path + " has " + name + " '" + text +
                "'; expected an integer in [1, " + std::to_string(max) + "]");
  return uint32_t(*value);
}

// The stored pixel format the series shares.
struct PixelLayout {
  uint32_t bitsAllocated = 16, bitsStored = 16;
  bool isSigned = false;
};

// The sample type that holds every value stored * slope + intercept of the series exactly, where slopes and
// intercepts are integers; float32 otherwise.
SampleType sampleTypeFor(const PixelLayout& layout, const std::vector<DicomImage>& slices) {
  const double storedLo = layout.isSigned ? -std::ldexp(1.0, int(layout.bitsStored) - 1) : 0.0;
  const double storedHi = layout.isSigned ? std::ldexp(1.0, int(layout.bitsStored) - 1) - 1.0
                                          : std::ldexp(1.0, int(layout.bitsStored)) - 1.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const DicomImage& slice : slices) {
    if (slice.slope != std::floor(slice.slope) || slice.intercept != std::floor(slice.intercept))
      return SampleType::Float32;
    for (const double stored : {storedLo, storedHi}) {
      lo = std::min(lo, stored * slice.slope + slice.intercept);
      hi = std::max(hi, stored * slice.slope + slice.intercept);
    }
  }
  return integerTypeHolding(lo, hi, layout.bitsAllocated == 8);
}

// An image's pixel data as GDCM decodes it: frames one after another, samples of `bitsAllocated` bits. With
// the spacing and rescale GDCM finds for it, in the header or (enhanced images) in its functional groups.
struct DecodedImage {
  uint32_t bitsAllocated = 16, bitsStored = 16;
  bool isSigned = false;
  std::vector<char> pixels;
  glm::dvec3 spacing{1.0};
  double slope = 1.0, intercept = 0.0;
  // Where an enhanced image places its frames (its functional groups): a position for every frame, or none,
  // and the pixel spacing there (GDCM gives none for frames it finds out of order).
  std::vector<glm::dvec3> framePositions;
  std::optional<std::vector<double>> frameOrientation, framePixelSpacing;
};

// The frames' Image Position (Patient) from the per-frame functional groups, and the orientation and pixel
// spacing from the shared ones (else the first frame's), where `ds` has them for all `frames`.
void readFramePlacement(const gdcm::DataSet& ds, uint32_t frames, DecodedImage& decoded) {
  const gdcm::SmartPointer<gdcm::SequenceOfItems> perFrame = itemsOf(ds, kPerFrameGroups);
  if (!perFrame || perFrame->GetNumberOfItems() != frames) return;
  const gdcm::SmartPointer<gdcm::SequenceOfItems> shared = itemsOf(ds, kSharedGroups);
  const auto sharedText = [&](const gdcm::Tag& group, const gdcm::Tag& tag) {
    const std::string text = shared ? groupText(shared->GetItem(1).GetNestedDataSet(), group, tag) : "";
    return text.empty() ? groupText(perFrame->GetItem(1).GetNestedDataSet(), group, tag) : text;
  };
  const std::string orientation = sharedText(kPlaneOrientation, kOrientation);
  decoded.framePixelSpacing = numbersOf(sharedText(kPixelMeasures, kPixelSpacing), 2);
  std::vector<glm::dvec3> positions;
  for (uint32_t frame = 1; frame <= frames; ++frame) {
    const auto p =
        numbersOf(groupText(perFrame->GetItem(frame).GetNestedDataSet(), kPlanePosition, kPosition), 3);
    if (!p) return;
    positions.emplace_back((*p)[0], (*p)[1], (*p)[2]);
  }
  decoded.frameOrientation = numbersOf(orientation, 6);
  if (decoded.frameOrientation) decoded.framePositions = std::move(positions);
}

// Decodes `path`, checking that it holds `frames` gray frames of the size the volume has.
DecodedImage decodeImage(const std::string& path, glm::u32vec3 dims, uint32_t frames) {
  gdcm::ImageReader reader;
  reader.SetFileName(path.c_str());
  captureGdcmMessages();
  const GdcmReading reading(path);
  if (!reader.Read())
    throw Error("cannot read DICOM image " + path + " (GDCM could not decode it" + gdcmWords() + ")");
  const gdcm::Image& image = reader.GetImage();
  const gdcm::PixelFormat& format = image.GetPixelFormat();
  DecodedImage decoded;
  decoded.bitsAllocated = format.GetBitsAllocated();
  decoded.bitsStored = std::clamp<uint32_t>(format.GetBitsStored(), 1, decoded.bitsAllocated);
  decoded.isSigned = format.GetPixelRepresentation() == 1;
  const uint32_t decodedFrames = image.GetNumberOfDimensions() > 2 ? image.GetDimension(2) : 1;
  const uint32_t bits = decoded.bitsAllocated;
  if (image.GetColumns() != dims.x || image.GetRows() != dims.y || decodedFrames != frames ||
      format.GetSamplesPerPixel() != 1 || (bits != 8 && bits != 16 && bits != 32))
    throw Error("DICOM image " + path + " decodes to " + std::to_string(decodedFrames) + " frame(s) of " +
                std::to_string(image.GetColumns()) + "x" + std::to_string(image.GetRows()) + " pixels of " +
                std::to_string(format.GetSamplesPerPixel()) + " samples of " + std::to_string(bits) +
                " bits; its header says " + std::to_string(frames) + " of " + std::to_string(dims.x) + "x" +
                std::to_string(dims.y) + " of 1 sample");
  // GDCM copies native (uncompressed) pixel data as long as the image's size says, past the end of an
  // element that is shorter.
  const size_t bytes = size_t(dims.x) * dims.y * frames * (bits / 8);
  if (const gdcm::DataElement& data = image.GetDataElement(); !data.GetSequenceOfFragments()) {
    const gdcm::ByteValue* value = data.GetByteValue();
    if (!value || uint64_t(value->GetLength()) < bytes)
      throw Error("cannot read DICOM image " + path + ": its pixel data holds " +
                  std::to_string(value ? uint64_t(value->GetLength()) : uint64_t(0)) +
                  " bytes, and its header says " + std::to_string(bytes) + " (" + std::to_string(frames) +
                  " frame(s) of " + std::to_string(dims.x) + "x" + std::to_string(dims.y) + " pixels of " +
                  std::to_string(bits) + " bits)");
  }
  decoded.pixels.resize(image.GetBufferLength());
  if (decoded.pixels.size() < bytes || !image.GetBuffer(decoded.pixels.data()))
    throw Error("cannot read DICOM image " + path + ": its pixel data is shorter than its header says");
  decoded.spacing = {image.GetSpacing(0), image.GetSpacing(1), image.GetSpacing(2)};
  decoded.slope = image.GetSlope();
  decoded.intercept = image.GetIntercept();
  if (frames > 1) readFramePlacement(reader.GetFile().GetDataSet(), frames, decoded);
  return decoded;
}

// Puts the frames of `image`, each `framePixels` pixels, in `order` (order[k]: the frame to put k-th).
void reorderFrames(DecodedImage& image, const std::vector<size_t>& order, size_t framePixels) {
  if (std::is_sorted(order.begin(), order.end())) return;
  const size_t frameBytes = framePixels * (image.bitsAllocated / 8);
  std::vector<char> ordered(image.pixels.size());
  for (size_t k = 0; k < order.size(); ++k)
    std::memcpy(ordered.data() + k * frameBytes, image.pixels.data() + order[k] * frameBytes, frameBytes);
  image.pixels = std::move(ordered);
}

// Pixels [first, first + count) of `image` as stored * slope + intercept, in `type`, into `out`. Bits above
// Bits Stored may hold overlays: they are masked off, and the sign is the highest stored bit's.
void rescaleInto(const DecodedImage& image, size_t first, size_t count, double slope, double intercept,
                 SampleType type, std::span<std::byte> out) {
  const uint32_t bits = image.bitsAllocated, stored = image.bitsStored;
  const uint64_t mask = (1ull << stored) - 1;
  const char* bytes = image.pixels.data() + first * (bits / 8);
  const auto storedValue = [&](size_t i) -> int64_t {
    uint64_t raw = 0;
    if (bits == 8) raw = uint8_t(bytes[i]);
    if (bits == 16) {
      uint16_t v;
      std::memcpy(&v, bytes + 2 * i, 2);
      raw = v;
    }
    if (bits == 32) {
      uint32_t v;
      std::memcpy(&v, bytes + 4 * i, 4);
      raw = v;
    }
    raw &= mask;
    if (image.isSigned && (raw >> (stored - 1)) & 1) return int64_t(raw) - int64_t(mask) - 1;
    return int64_t(raw);
  };
  forSampleType(type, [&](auto zero) {
    using T = decltype(zero);
    T* samples = reinterpret_cast<T*>(out.data());
    for (size_t i = 0; i < count; ++i) samples[i] = T(double(storedValue(i)) * slope + intercept);
  });
}

// Single-frame images, one per slice, each decoded as its slice is read.
class DicomSeriesSource final : public VolumeSource {
 public:
  DicomSeriesSource(std::vector<DicomImage> slices, VolumeInfo info)
      : slices_(std::move(slices)), info_(std::move(info)) {}

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const size_t pixels = size_t(info_.dims.x) * info_.dims.y;
    for (uint32_t i = 0; i < count; ++i) {
      const DicomImage& slice = slices_[z0 + i];
      rescaleInto(decodeImage(slice.path, info_.dims, 1), 0, pixels, slice.slope, slice.intercept, info_.type,
                  out.subspan(i * info_.sliceBytes(), info_.sliceBytes()));
    }
  }

  std::vector<DicomImage> slices_;
  VolumeInfo info_;
};

// One multi-frame image, a frame per slice in the file's order: GDCM decodes the pixel data whole, so it is
// decoded once, when opening, and held.
class DicomMultiFrameSource final : public VolumeSource {
 public:
  DicomMultiFrameSource(DecodedImage decoded, VolumeInfo info)
      : decoded_(std::move(decoded)), info_(std::move(info)) {}

  const VolumeInfo& info() const override { return info_; }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    const size_t pixels = size_t(info_.dims.x) * info_.dims.y;
    rescaleInto(decoded_, z0 * pixels, count * pixels, decoded_.slope, decoded_.intercept, info_.type, out);
  }

  DecodedImage decoded_;
  VolumeInfo info_;
};

// The normal of an Image Orientation (Patient) (row and column directions); throws naming `what` where the
// two are not perpendicular unit vectors.
glm::dvec3 normalOf(const std::vector<double>& o, const std::string& what) {
  const glm::dvec3 normal = glm::cross(glm::dvec3(o[0], o[1], o[2]), glm::dvec3(o[3], o[4], o[5]));
  if (!(glm::length(normal) > 0.5))
    throw Error(what +
                " has Image Orientation (Patient) whose directions are not perpendicular unit vectors");
  return normal;
}

// The axes of images stacked along their normal: x along the rows, y down the columns, z along the normal
// (core/orientation.h; DICOM's patient frame is LPS). The identity for directions that are not at right
// angles (normalOf has refused the parallel ones).
AxisDirections axesOf(const std::vector<double>& o) {
  const glm::dvec3 row(o[0], o[1], o[2]), column(o[3], o[4], o[5]);
  return axisDirectionsOf(row, column, glm::cross(row, column)).value_or(AxisDirections(1.0));
}

// The order of `positions` along `normal` (stable): order[k] is the image stacked k-th. Two at one position
// throw samePosition(a, b), the message naming them.
std::vector<size_t> stackAlongNormal(const std::vector<glm::dvec3>& positions, const glm::dvec3& normal,
                                     const std::function<std::string(size_t, size_t)>& samePosition) {
  std::vector<size_t> order(positions.size());
  std::iota(order.begin(), order.end(), size_t(0));
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return glm::dot(positions[a], normal) < glm::dot(positions[b], normal);
  });
  if (positions.size() < 2) return order;
  const double extent = glm::dot(positions[order.back()] - positions[order.front()], normal);
  for (size_t k = 1; k < positions.size(); ++k) {
    const size_t below = order[k - 1], above = order[k];
    if (glm::dot(positions[above] - positions[below], normal) <= 1e-6 * std::max(1.0, std::abs(extent)))
      throw Error(samePosition(below, above));
  }
  return order;
}

// The spacing across slices at `positions` (stacking order), of a volume `info` whose dims, in-plane spacing
// and axes are set: their average gap (none for one slice), with the grid they are resampled onto in `grid`
// where they lie off a regular stack (planSlices), and what is said of it in `notes`.
std::optional<double> placeSlicesOf(const VolumeInfo& info, const std::vector<glm::dvec3>& positions,
                                    const std::string& what, std::optional<SliceGrid>& grid,
                                    std::vector<std::string>& notes) {
  if (positions.size() < 2) return std::nullopt;
  SlicePlan plan = planSlices(info, positions, what);
  notes.insert(notes.end(), plan.notes.begin(), plan.notes.end());
  grid = std::move(plan.grid);
  return plan.averageGap;
}

// A series that holds each position the same number of times, N > 1 (a 4D CT's phases, a perfusion study's
// time points): the images of time point `picked` (options' --time), one per position, told apart at each
// position by Temporal Position Identifier, else Acquisition Number, else Instance Number (where every image
// has it and they differ at each position). `slices` is left as it is, and nullopt returned, for a series of
// one image per position or one whose positions repeat unevenly or cannot be told apart (refused when
// stacked).
std::optional<PickedVolume> pickTimePoint(std::vector<DicomImage>& slices, const SourceOptions& options,
                                          const std::string& listed) {
  // Images at one position: their positions along the normal and in the plane agree within a micron.
  std::map<std::tuple<long long, long long, long long>, std::vector<size_t>> atPosition;
  for (size_t i = 0; i < slices.size(); ++i) {
    const glm::dvec3 p = *slices[i].position;
    atPosition[{std::llround(p.x * 1e3), std::llround(p.y * 1e3), std::llround(p.z * 1e3)}].push_back(i);
  }
  const size_t count = atPosition.begin()->second.size();
  if (count < 2 || atPosition.size() * count != slices.size() ||
      std::any_of(atPosition.begin(), atPosition.end(),
                  [&](const auto& p) { return p.second.size() != count; }))
    return std::nullopt;
  using Key = std::optional<double> DicomImage::*;
  std::optional<Key> byKey;
  for (const Key key : {&DicomImage::temporalPosition, &DicomImage::acquisition, &DicomImage::instance}) {
    bool apart = true;
    for (const auto& [position, members] : atPosition) {
      std::set<double> values;
      for (const size_t i : members)
        if (const auto& v = slices[i].*key) values.insert(*v);
      apart = apart && values.size() == members.size();
    }
    if (apart) {
      byKey = key;
      break;
    }
  }
  if (!byKey) return std::nullopt;
  const PickedVolume picked = pickVolume(options, {count, 1}, "DICOM series " + listed);
  std::vector<DicomImage> chosen;
  for (auto& [position, members] : atPosition) {
    std::sort(members.begin(), members.end(),
              [&](size_t a, size_t b) { return *(slices[a].*(*byKey)) < *(slices[b].*(*byKey)); });
    chosen.push_back(std::move(slices[members[picked.timePoint]]));
  }
  slices = std::move(chosen);
  return picked;
}

// Sorts a series' slices into the order they are stacked in, and returns their positions in that order; none
// where they are stacked by Instance Number. What a person should hear about the stacking goes to `notes`;
// of a series of several time points (pickTimePoint), the one --time picks is stacked, said in `picked`.
std::vector<glm::dvec3> stackSlices(std::vector<DicomImage>& slices, const std::string& listed,
                                    const SourceOptions& options, std::optional<PickedVolume>& picked,
                                    std::vector<std::string>& notes) {
  const bool positioned = std::all_of(slices.begin(), slices.end(),
                                      [](const DicomImage& s) { return s.position && s.orientation; });
  if (positioned) {
    // Every image is oriented as the first listed, whose normal orders them.
    const DicomImage& listedFirst = slices.front();
    for (const DicomImage& slice : slices)
      for (size_t i = 0; i < 6; ++i)
        if (std::abs((*slice.orientation)[i] - (*listedFirst.orientation)[i]) > 1e-4)
          throw Error(
              "DICOM image " + slice.path + " is oriented otherwise than " + listedFirst.path +
              " (Image Orientation (Patient)); a series of one orientation is read (a localizer among "
              "the slices?)");
    const glm::dvec3 normal = normalOf(*listedFirst.orientation, "DICOM image " + listedFirst.path);
    picked = pickTimePoint(slices, options, listed);
    std::vector<glm::dvec3> positions;
    for (const DicomImage& slice : slices) positions.push_back(*slice.position);
    const std::vector<size_t> order = stackAlongNormal(positions, normal, [&](size_t a, size_t b) {
      return "DICOM images " + slices[a].path + " and " + slices[b].path +
             " lie at one position; a series of one image per position is read (several acquisitions or "
             "echoes in one series?)";
    });
    std::vector<DicomImage> stacked;
    std::vector<glm::dvec3> stackedPositions;
    for (const size_t i : order) {
      stacked.push_back(std::move(slices[i]));
      stackedPositions.push_back(positions[i]);
    }
    slices = std::move(stacked);
    return stackedPositions;
  }
  if (std::all_of(slices.begin(), slices.end(), [](const DicomImage& s) { return s.instance; })) {
    std::stable_sort(slices.begin(), slices.end(),
                     [](const DicomImage& a, const DicomImage& b) { return *a.instance < *b.instance; });
    notes.push_back(
        "the DICOM images have no Image Position and Orientation (Patient); they are stacked by Instance "
        "Number");
    return {};
  }
  throw Error("DICOM images of " + listed + " have neither Image Position and Orientation (Patient) nor " +
              "Instance Number (e.g. " + slices.front().path + "); their order is unknown");
}

}  // namespace

std::unique_ptr<VolumeSource> openDicomSource(const std::string& spec, const SourceOptions& options) {
  std::error_code ec;
  const bool isFolder = fs::is_directory(spec, ec);
  const std::string folder = isFolder ? spec : fs::path(spec).parent_path().string();
  const std::string listed = folder.empty() ? "." : folder;
  std::vector<DicomImage> images = scanImages(listDicomFiles(listed), listed);
  // A folder without images of its own, as exports and discs lay them out: a DICOMDIR beside the folders of
  // the series, which are searched for their images.
  const bool searchedBelow = images.empty();
  if (searchedBelow) images = scanImages(listDicomFilesBelow(listed), listed);
  if (images.empty())
    throw Error(
        "DICOM folder " + listed +
        " has no DICOM images (files that begin with the DICM signature and hold Rows and Columns), nor "
        "has any of its folders " +
        std::to_string(kDicomSearchDepth) + " levels down");

  // The series: the one the given image belongs to, or the folder's only one.
  std::map<std::string, std::vector<const DicomImage*>> bySeries;
  for (const DicomImage& image : images) bySeries[image.seriesUid].push_back(&image);
  std::string seriesUid;
  if (!isFolder && !searchedBelow) {
    const auto given = std::find_if(images.begin(), images.end(), [&](const DicomImage& image) {
      return fs::equivalent(image.path, spec, ec);
    });
    if (given == images.end())
      throw Error(
          spec +
          " is a DICOM file without an image (a DICOMDIR or a report?); give the folder of a series or "
          "one of its images");
    seriesUid = given->seriesUid;
  } else if (bySeries.size() > 1) {
    std::string list;
    for (const auto& [uid, members] : bySeries) list += "\n  " + seriesSummary(members);
    throw Error("DICOM folder " + listed + " holds " + std::to_string(bySeries.size()) + " series" +
                (searchedBelow ? " in its folders" : "") +
                "; give one image of the series to convert (its folder's images of that series are "
                "read):" +
                list);
  } else {
    seriesUid = bySeries.begin()->first;
  }
  std::vector<DicomImage> slices;
  for (DicomImage& image : images)
    if (image.seriesUid == seriesUid) slices.push_back(std::move(image));

  const DicomImage& first = slices.front();
  for (const DicomImage& slice : slices) {
    if (slices.size() > 1 && !slice.frames.empty() && slice.frames != "1")
      throw Error("DICOM image " + slice.path + " holds " + slice.frames + " frames, and its series " +
                  std::to_string(slices.size()) +
                  " images; a series is read as single-frame images, or as one multi-frame image");
    checkSameFormat(first, slice);
  }
  if (first.samplesPerPixel != "1" && !first.samplesPerPixel.empty())
    throw Error("DICOM image " + first.path + " has " + first.samplesPerPixel + " samples per pixel (" +
                first.photometric + "); a volume is read from gray images (MONOCHROME1 or MONOCHROME2)");
  PixelLayout layout;
  layout.bitsAllocated = positiveInteger(first, first.bitsAllocated, "Bits Allocated", 32);
  if (layout.bitsAllocated != 8 && layout.bitsAllocated != 16 && layout.bitsAllocated != 32)
    throw Error("DICOM image " + first.path + " has Bits Allocated " + first.bitsAllocated +
                "; expected 8, 16 or 32");
  layout.bitsStored = first.bitsStored.empty()
                          ? layout.bitsAllocated
                          : positiveInteger(first, first.bitsStored, "Bits Stored", layout.bitsAllocated);
  layout.isSigned = first.pixelRepresentation == "1";
  const glm::u32vec3 sliceDims(positiveInteger(first, first.columns, "Columns", kMaxDimsPerAxis),
                               positiveInteger(first, first.rows, "Rows", kMaxDimsPerAxis), 1);
  const std::string seriesText = seriesUid.empty() ? "without UID" : seriesUid;
  const std::string monochrome1Note =
      "the DICOM images are MONOCHROME1 (viewers show 0 as white); the volume keeps their values, so what a "
      "viewer shows dark is high in the volume";

  VolumeInfo info;
  std::vector<std::string> notes;
  std::optional<SliceGrid> grid;  // where the slices must be resampled to lie where their positions say
  if (first.photometric == "MONOCHROME1") notes.push_back(monochrome1Note);
  if (!first.frames.empty() && first.frames != "1") {
    pickVolume(options, {}, "DICOM image " + first.path);  // one volume: --time or --channel 0 alone
    info.dims = sliceDims;
    info.dims.z = positiveInteger(first, first.frames, "Number of Frames", kMaxDimsPerAxis);
    DecodedImage decoded = decodeImage(first.path, info.dims, info.dims.z);
    DicomImage rescale = first;  // GDCM's rescale, which enhanced images keep in functional groups
    rescale.slope = decoded.slope;
    rescale.intercept = decoded.intercept;
    info.type = sampleTypeFor(layout, {rescale});
    // The frames of an enhanced image that places each one are stacked as a series' slices are, along their
    // normal. Else Spacing Between Slices where the header has it (NM, some MR), or GDCM's spacing from the
    // functional groups of enhanced images. Without either the frames are frames in time (a cine), for which
    // GDCM gives Frame Time as the spacing: they are stacked at the pixel spacing instead.
    const bool enhanced = std::find(std::begin(kEnhancedSopClasses), std::end(kEnhancedSopClasses),
                                    first.sopClass) != std::end(kEnhancedSopClasses);
    const std::optional<double> between = numberOf(first.spacingBetweenSlices);
    if (enhanced && !decoded.framePositions.empty()) {
      const std::string image = "DICOM image " + first.path;
      const std::vector<size_t> order = stackAlongNormal(
          decoded.framePositions, normalOf(*decoded.frameOrientation, image), [&](size_t a, size_t b) {
            return "frames " + std::to_string(a + 1) + " and " + std::to_string(b + 1) + " of " + image +
                   " lie at one position; a multi-frame image of one frame per position is read (several "
                   "stacks, echoes or time points in one image?)";
          });
      reorderFrames(decoded, order, size_t(sliceDims.x) * sliceDims.y);
      std::vector<glm::dvec3> positions;
      for (const size_t i : order) positions.push_back(decoded.framePositions[i]);
      info.axes = axesOf(*decoded.frameOrientation);
      info.origin = positions.front();  // the first frame stacked
      info.patientFrame = true;
      if (const auto& pixel = decoded.framePixelSpacing; pixel && (*pixel)[0] > 0 && (*pixel)[1] > 0)
        decoded.spacing.x = (*pixel)[1], decoded.spacing.y = (*pixel)[0];  // row spacing first
      if (!options.spacing) {
        info.spacing = decoded.spacing;
        if (const auto across = placeSlicesOf(info, positions, "the frames of " + image, grid, notes))
          decoded.spacing.z = *across;
      }
    } else if (between && *between > 0) {
      decoded.spacing.z = *between;
    } else if (!enhanced) {
      decoded.spacing.z = decoded.spacing.x;
      if (!options.spacing)
        notes.push_back(
            "the frames of DICOM image " + first.path +
            " say no spacing between them (frames in time, a cine?); they are stacked at the pixel "
            "spacing (--spacing sets it)");
    }
    info.spacing = options.spacing.value_or(decoded.spacing);
    if (!isValidSpacing(info.spacing))
      throw Error("DICOM image " + first.path + " has spacing " + formatSpacing(info.spacing) +
                  "; expected " + validSpacingText() + " (--spacing sets it)");
    info.description =
        "dicom:" + first.path + " (series " + seriesText + ", " + std::to_string(info.dims.z) + " frames)";
    info.notes = std::move(notes);
    auto source = std::make_unique<DicomMultiFrameSource>(std::move(decoded), std::move(info));
    if (grid) return resampleSlices(std::move(source), std::move(*grid));
    return source;
  }
  std::optional<PickedVolume> picked;
  const std::vector<glm::dvec3> positions = stackSlices(slices, listed, options, picked, notes);
  if (!picked) picked = pickVolume(options, {}, "DICOM series " + listed);
  const DicomImage& bottom = slices.front();  // the slices are in their stacking order now
  info.dims = {sliceDims.x, sliceDims.y, uint32_t(slices.size())};
  if (!positions.empty()) {
    info.axes = axesOf(*bottom.orientation);  // stacked along their normal
    info.origin = positions.front();
    info.patientFrame = true;
  }
  if (options.spacing) {
    info.spacing = *options.spacing;
  } else {
    const auto pixelSpacing = numbersOf(bottom.pixelSpacing, 2);
    if (pixelSpacing && (*pixelSpacing)[0] > 0 && (*pixelSpacing)[1] > 0)
      info.spacing = {(*pixelSpacing)[1], (*pixelSpacing)[0], (*pixelSpacing)[0]};
    else
      notes.push_back(
          "the DICOM images have no Pixel Spacing; the volume takes 1 per sample (--spacing sets it)");
    std::optional<double> across = placeSlicesOf(info, positions, "the DICOM slices", grid, notes);
    if (!across)
      if (const auto thickness = numberOf(bottom.sliceThickness); thickness && *thickness > 0)
        across = *thickness;
    if (across) info.spacing.z = *across;
    if (!across && pixelSpacing)
      notes.push_back(
          "the spacing across the DICOM slices is unknown (no positions, or one slice, and no Slice "
          "Thickness); it takes the spacing between rows (--spacing sets it)");
    if (!isValidSpacing(info.spacing))
      throw Error("DICOM series of " + bottom.path + " has spacing " + formatSpacing(info.spacing) +
                  "; expected " + validSpacingText() + " (--spacing sets it)");
  }
  info.type = sampleTypeFor(layout, slices);
  info.description =
      "dicom:" + listed + " (series " + seriesText + ", " + std::to_string(slices.size()) + " images)";
  info.notes = std::move(notes);
  describePicked(info, *picked);
  auto source = std::make_unique<DicomSeriesSource>(std::move(slices), std::move(info));
  if (grid) return resampleSlices(std::move(source), std::move(*grid));
  return source;
}

}  // namespace ropecast
