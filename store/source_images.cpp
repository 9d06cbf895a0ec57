#include "store/source_images.h"

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <vector>

#include "core/error.h"
#include "core/input_file.h"
#include "store/picked_volume.h"
#include "store/slice_files.h"
#include "store/tiff_directories.h"
#include "store/tiff_page_reader.h"
#include "store/tiff_stack_layout.h"

namespace ropecast {
namespace {

namespace fs = std::filesystem;

// One slice: a file, and its page for multi-page TIFFs.
struct SliceRef {
  std::string path;
  int page = 0;
};

struct SliceFormat {
  uint32_t width = 0;
  uint32_t height = 0;
  SampleType type = SampleType::UInt8;
  // The file's bits per sample when fewer than the type holds (1-bit PNG, 12-bit TIFF): OpenImageIO scales
  // them up to the type's range, and they are scaled back to the file's values; else 0.
  uint32_t narrowBits = 0;
  // TIFF's MinIsWhite: viewers show 0 as white. The volume keeps the stored values, as at every other bit
  // depth; OpenImageIO inverts 8-bit (and narrower) ones, which is undone.
  bool minIsWhite = false;
  // 1: gray; 3 or 4: RGB or RGBA (a palette image too, which OpenImageIO expands), read as gray from R when
  // R = G = B (and alpha is opaque) at every pixel, which only the pixels tell (grayFromColor).
  uint32_t channels = 1;
};

std::string describe(const SliceRef& slice, bool multiPage) {
  return multiPage ? slice.path + " (page " + std::to_string(slice.page) + ")" : slice.path;
}

std::string oiioError(const OIIO::ImageInput* in) {
  std::string message = in ? in->geterror() : OIIO::geterror();
  if (message.empty()) message = "unknown OpenImageIO error";
  return message;
}

// The bit depth of a grayscale PNG's samples (1, 2, 4, 8 or 16) from its header; 0 for other files.
uint32_t grayPngBitDepth(const std::string& path) {
  std::array<unsigned char, 26> header{};  // signature, then the IHDR chunk up to its color type
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(header.data()), header.size())) return 0;
  static constexpr std::array<unsigned char, 8> kSignature{0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  const bool gray = std::equal(kSignature.begin(), kSignature.end(), header.begin()) &&
                    std::memcmp(&header[12], "IHDR", 4) == 0 && header[25] == 0;
  return gray ? header[24] : 0;
}

// The spec OpenImageIO gives, with the bits per sample of a PNG: it widens 1-, 2- and 4-bit grayscale to 8
// bits (a bilevel image reads 0 and 255) and does not say so, where a TIFF says.
OIIO::ImageSpec withFileBits(OIIO::ImageSpec spec, const OIIO::ImageInput& in, const std::string& path) {
  if (spec.get_int_attribute("oiio:BitsPerSample", 0) == 0 && std::string_view(in.format_name()) == "png")
    if (const uint32_t bits = grayPngBitDepth(path)) spec.attribute("oiio:BitsPerSample", int(bits));
  return spec;
}

// OpenImageIO's messages may run to a line per strip.
std::string firstLine(const std::string& message) {
  return message.substr(0, message.find('\n'));
}

std::unique_ptr<OIIO::ImageInput> openImage(const std::string& path) {
  requireRegularFile(path, "cannot read image " + path);  // before OpenImageIO's open, which waits on a FIFO
  // Alpha as the file stores it: OpenImageIO would otherwise multiply the color channels by it.
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path, &config);
  if (!in) throw Error("cannot read image " + path + ": " + oiioError(nullptr));
  return in;
}

// The pages of a multi-page TIFF: walked by tiffPageCount where the file is a TIFF (to reach page n,
// OpenImageIO's TIFF reader walks the n directories before it, so counting by its seeks took time in the
// square of the pages: minutes for thousands), else counted by OpenImageIO's input `in`.
int countPages(OIIO::ImageInput& in, const std::string& path) {
  if (const std::optional<int> tiffPages = tiffPageCount(path)) return *tiffPages;
  int pages = 1;
  while (in.seek_subimage(pages, 0)) ++pages;
  return pages;
}

// The sample types of OpenImageIO's pixel types. Half floats are read as float32, which holds each exactly.
constexpr std::pair<OIIO::TypeDesc::BASETYPE, SampleType> kPixelTypes[] = {
    {OIIO::TypeDesc::UINT8, SampleType::UInt8},   {OIIO::TypeDesc::INT8, SampleType::Int8},
    {OIIO::TypeDesc::UINT16, SampleType::UInt16}, {OIIO::TypeDesc::INT16, SampleType::Int16},
    {OIIO::TypeDesc::UINT32, SampleType::UInt32}, {OIIO::TypeDesc::INT32, SampleType::Int32},
    {OIIO::TypeDesc::FLOAT, SampleType::Float32}, {OIIO::TypeDesc::DOUBLE, SampleType::Float64},
    {OIIO::TypeDesc::HALF, SampleType::Float32}};

// The pixel type a slice of `type` is read as (OpenImageIO converts half to it).
OIIO::TypeDesc pixelTypeOf(SampleType type) {
  for (const auto& [pixelType, sampleType] : kPixelTypes)
    if (sampleType == type) return pixelType;
  throw Error("no image pixel type for sample type " + std::string(sampleTypeName(type)));
}

// OpenImageIO's TIFF reader copies samples of 64 bits when it reads whole strips, but leaves them out (zeros,
// and no error) when it reads one row or one tile at a time: in a TIFF one row high, or a tiled one. Of a
// tiled TIFF it also leaves out samples of 17 to 31 bits. Such a file is refused rather than read as zeros.
void refuseWhatOpenImageIOReadsAsZeros(const OIIO::ImageSpec& spec, std::string_view formatName, int bits,
                                       const std::string& what) {
  if (formatName != "tiff") return;
  const std::string samples = std::to_string(bits) + "-bit samples";
  if (spec.tile_width > 0 && bits > 16 && bits != 32)
    throw Error("image slice " + what + " is a tiled TIFF of " + samples +
                ", which OpenImageIO reads as zeros; expected one in strips (not tiled)");
  if (spec.height == 1 && bits == 64)
    throw Error("image slice " + what + " is a TIFF of " + samples +
                " one row high, which OpenImageIO reads as zeros; expected slices of two rows or more");
}

// `formatName`: OpenImageIO's name of the file's format ("tiff", "png", ...).
SliceFormat sliceFormat(const OIIO::ImageSpec& spec, std::string_view formatName, const std::string& what) {
  static const std::vector<std::string> kGrayAlpha{"Y", "A"}, kRgb{"R", "G", "B"}, kRgba{"R", "G", "B", "A"};
  const std::vector<std::string> names(spec.channelnames.begin(), spec.channelnames.end());
  if (spec.nchannels != 1 && names != kGrayAlpha && names != kRgb && names != kRgba) {
    std::string listed;
    for (const std::string& name : names) listed += (listed.empty() ? "" : ", ") + name;
    throw Error("image slice " + what + " has " + std::to_string(spec.nchannels) + " channels (" + listed +
                "); expected a single-channel (grayscale) image, gray with an opaque alpha, or RGB or RGBA "
                "with equal color channels");
  }
  if (spec.depth > 1) throw Error("image slice " + what + " is a 3D image; expected 2D slices");
  if (spec.width <= 0 || spec.height <= 0) throw Error("image slice " + what + " is empty");
  SliceFormat format{uint32_t(spec.width), uint32_t(spec.height)};
  const auto* known = std::find_if(std::begin(kPixelTypes), std::end(kPixelTypes),
                                   [&](const auto& p) { return spec.format == p.first; });
  if (known == std::end(kPixelTypes))
    throw Error("image slice " + what + " has pixel type " + std::string(spec.format.c_str()) +
                "; expected " + std::string(kSampleTypeList) + " (or 16-bit float, read as float32)");
  format.type = known->second;
  const uint32_t typeBits = uint32_t(8 * bytesPerSample(format.type));
  const int bits = spec.get_int_attribute("oiio:BitsPerSample", 0);
  refuseWhatOpenImageIOReadsAsZeros(spec, formatName, bits > 0 ? bits : int(typeBits), what);
  const bool isFloat = format.type == SampleType::Float32 || format.type == SampleType::Float64;
  // Palette images come expanded to 8-bit colors, their oiio:BitsPerSample 8 whatever their indexes' bits.
  if (bits > 0 && !isFloat && uint32_t(bits) < typeBits) {
    if (format.type == SampleType::Int8 || format.type == SampleType::Int16 ||
        format.type == SampleType::Int32)
      throw Error("image slice " + what + " has signed " + std::to_string(bits) +
                  "-bit samples; expected 8, 16 or 32 bits, or unsigned samples");
    format.narrowBits = uint32_t(bits);
  }
  format.minIsWhite = spec.get_int_attribute("tiff:PhotometricInterpretation", 1) == 0;
  format.channels = uint32_t(spec.nchannels);
  return format;
}

std::string photometricName(const SliceFormat& format) {
  return format.minIsWhite ? "MinIsWhite" : format.channels > 2 ? "RGB" : "MinIsBlack";
}

// A sample as a number (int8 and uint8 too), with the digits that tell floats apart.
template <typename T>
std::string sampleText(T value) {
  std::ostringstream text;
  text.precision(std::numeric_limits<T>::max_digits10);
  text << +value;
  return text.str();
}

// The gray of gray+alpha, RGB or RGBA `pixels` (`channels` samples each, `width` to a row) into `gray`: the
// first channel, where R, G and B are the same sample and alpha is the type's maximum (1 for floats); else an
// error naming the first pixel that is not gray.
template <typename T>
void grayFromColor(std::span<const std::byte> pixels, uint32_t channels, uint32_t width,
                   std::span<std::byte> gray, const std::string& what) {
  const T* pixel = reinterpret_cast<const T*>(pixels.data());
  T* out = reinterpret_cast<T*>(gray.data());
  const T opaque = std::is_floating_point_v<T> ? T(1) : std::numeric_limits<T>::max();
  const auto at = [&](size_t i) {
    return "pixel (" + std::to_string(i % width) + ", " + std::to_string(i / width) + ")";
  };
  for (size_t i = 0; i < gray.size() / sizeof(T); ++i, pixel += channels) {
    // Bit for bit, so that a NaN gray is gray too.
    if (channels > 2 && (std::memcmp(&pixel[0], &pixel[1], sizeof(T)) != 0 ||
                         std::memcmp(&pixel[0], &pixel[2], sizeof(T)) != 0))
      throw Error("image slice " + what + " has color channels that differ at " + at(i) + ": R " +
                  sampleText(pixel[0]) + ", G " + sampleText(pixel[1]) + ", B " + sampleText(pixel[2]) +
                  "; expected a grayscale image, or color channels equal at every pixel");
    if ((channels == 2 || channels == 4) && pixel[channels - 1] != opaque)
      throw Error("image slice " + what + " has alpha " + sampleText(pixel[channels - 1]) + " at " + at(i) +
                  "; expected a grayscale image, or alpha opaque (" + sampleText(opaque) +
                  ") at every pixel");
    out[i] = pixel[0];
  }
}

void grayFromColor(std::span<const std::byte> pixels, const SliceFormat& format, std::span<std::byte> gray,
                   const std::string& what) {
  forSampleType(format.type, [&](auto zero) {
    grayFromColor<decltype(zero)>(pixels, format.channels, format.width, gray, what);
  });
}

template <typename T>
void shiftRight(std::span<std::byte> samples, uint32_t shift) {
  const std::span<T> values(reinterpret_cast<T*>(samples.data()), samples.size() / sizeof(T));
  for (T& v : values) v = T(v >> shift);
}

// Scales samples OpenImageIO widened from `bits` bits back to the file's values: it fills the type's range by
// shifting left and repeating the high bits below, so a right shift undoes either. (Unsigned types only.)
void narrowSamples(std::span<std::byte> samples, SampleType type, uint32_t bits) {
  const uint32_t shift = uint32_t(8 * bytesPerSample(type)) - bits;
  if (type == SampleType::UInt8)
    shiftRight<uint8_t>(samples, shift);
  else if (type == SampleType::UInt16)
    shiftRight<uint16_t>(samples, shift);
  else
    shiftRight<uint32_t>(samples, shift);
}

void checkSameFormat(const SliceFormat& first, const SliceFormat& slice, const std::string& firstWhat,
                     const std::string& what) {
  if (slice.width != first.width || slice.height != first.height)
    throw Error("image slice " + what + " is " + std::to_string(slice.width) + "x" +
                std::to_string(slice.height) + ", but " + firstWhat + " is " + std::to_string(first.width) +
                "x" + std::to_string(first.height) + "; all slices must have the same size");
  if (slice.type != first.type)
    throw Error("image slice " + what + " has type " + std::string(sampleTypeName(slice.type)) + ", but " +
                firstWhat + " has " + std::string(sampleTypeName(first.type)) +
                "; all slices must have one type");
  if (slice.narrowBits != first.narrowBits) {
    const auto bitsOf = [](const SliceFormat& f) {
      return std::to_string(f.narrowBits ? f.narrowBits : 8 * bytesPerSample(f.type));
    };
    throw Error("image slice " + what + " has " + bitsOf(slice) + "-bit samples, but " + firstWhat + " has " +
                bitsOf(first) + "-bit ones; all slices must have one bit depth");
  }
  // Opposite meanings of a stored value: one slice's dark is another's bright.
  if (slice.minIsWhite != first.minIsWhite)
    throw Error("image slice " + what + " is " + photometricName(slice) + ", but " + firstWhat + " is " +
                photometricName(first) + " (TIFF photometric interpretation); all slices must have one");
}

class ImageSliceSource final : public VolumeSource {
 public:
  // `multiPage`: OpenImageIO's input of the multi-page TIFF whose pages the slices are, and its pages'
  // layouts (tiffPageLayouts, where it is a TIFF); none for slices of their own files.
  ImageSliceSource(std::vector<SliceRef> slices, std::unique_ptr<OIIO::ImageInput> multiPage,
                   std::optional<std::vector<TiffPageLayout>> pageLayouts, std::string description,
                   const SourceOptions& options)
      : slices_(std::move(slices)),
        multiPage_(multiPage != nullptr),
        multiPageInput_(std::move(multiPage)),
        pageLayouts_(std::move(pageLayouts)) {
    // Check every slice now, so a bad stack fails before any conversion work; whether a color slice is gray
    // takes its pixels, and is checked as it is read. A page stored as the first one is (its directory says
    // so) reads as it does, and is checked as it is read too: seeking every page through OpenImageIO takes
    // time in the square of the pages (countPages).
    const auto storedAsFirst = [&](size_t z) {
      const auto& layouts = *pageLayouts_;
      const auto page = size_t(slices_[z].page), first = size_t(slices_.front().page);
      return page < layouts.size() && first < layouts.size() && layouts[page] == layouts[first];
    };
    size_t colorSlices = 0;
    std::string firstColor;
    for (size_t z = 0; z < slices_.size(); ++z) {
      if (z > 0 && pageLayouts_ && storedAsFirst(z)) continue;
      const SliceFormat slice = formatOf(slices_[z]);
      if (slice.channels > 1 && colorSlices++ == 0) firstColor = describe(slices_[z], multiPage_);
      if (z == 0)
        format_ = slice;
      else
        checkSameFormat(format_, slice, describe(slices_[0], multiPage_), describe(slices_[z], multiPage_));
    }
    info_.dims = {format_.width, format_.height, uint32_t(slices_.size())};
    info_.type = format_.type;
    info_.spacing = options.spacing.value_or(glm::dvec3(1.0));
    if (info_.type == SampleType::UInt8) {
      info_.valueMin = 0.0;
      info_.valueMax = format_.narrowBits ? double((1u << format_.narrowBits) - 1) : 255.0;
    }
    info_.description = std::move(description);
    if (format_.minIsWhite)
      addNote(
          "the TIFF slices are MinIsWhite (viewers show 0 as white); the volume keeps their stored values, "
          "so what a viewer shows dark is high in the volume");
    if (colorSlices > 0)
      addNote(
          (colorSlices == slices_.size()
               ? std::string("the slices are")
               : std::to_string(colorSlices) + " of the " + std::to_string(slices_.size()) +
                     " slices (first: " + firstColor + ") are") +
          " RGB, RGBA or gray+alpha images, read as gray (their first channel): each must have equal color "
          "channels and an opaque alpha at every pixel, or converting stops, naming the first pixel that "
          "does not");
  }

  const VolumeInfo& info() const override { return info_; }
  void addNote(std::string note) { info_.notes.push_back(std::move(note)); }
  void describeVolume(const PickedVolume& picked) { describePicked(info_, picked); }

 private:
  void readSlices(uint32_t z0, uint32_t count, std::span<std::byte> out) override {
    for (uint32_t i = 0; i < count; ++i)
      readSlice(slices_[z0 + i], out.subspan(i * info_.sliceBytes(), info_.sliceBytes()));
  }

  // The format of a slice (sliceFormat); a slice file of its own is checked to be whole and of one page.
  SliceFormat formatOf(const SliceRef& slice) {
    if (multiPage_) {
      OIIO::ImageSpec spec;
      OIIO::ImageInput& in = *multiPageInput_;
      if (!in.seek_subimage(slice.page, 0, spec))
        throw Error("cannot read image slice " + describe(slice, true) + ": " + oiioError(&in));
      return sliceFormat(spec, in.format_name(), describe(slice, true));
    }
    const auto in = openImage(slice.path);
    tiffPageCount(slice.path);  // refuses a TIFF cut short, whose missing data would read as zeros
    const OIIO::ImageSpec spec = withFileBits(in->spec(), *in, slice.path);
    const std::string formatName = in->format_name();
    // A multi-page TIFF among the slices would give its first page only.
    if (in->seek_subimage(1, 0))
      throw Error("image slice " + slice.path + " has " + std::to_string(countImagePages(slice.path)) +
                  " pages; convert a multi-page TIFF on its own, or give single-page slices");
    return sliceFormat(spec, formatName, slice.path);
  }

  // Whether the page is read through libtiff at its directory's offset (TiffPageReader), not through
  // OpenImageIO (whose TIFF reader walks every directory before a page to reach it): a page stored as the
  // first one, which TiffPageReader reads, of the bits and sample format of the stack's type, its values kept
  // as stored (OpenImageIO inverts 8-bit MinIsWhite ones, which readSlice undoes).
  const TiffPageLayout* readByDirectory(const SliceRef& slice) const {
    if (!pageLayouts_ || size_t(slice.page) >= pageLayouts_->size()) return nullptr;
    const TiffPageLayout& page = (*pageLayouts_)[size_t(slice.page)];
    const TiffPageLayout& first = (*pageLayouts_)[size_t(slices_.front().page)];
    const bool isFloat = format_.type == SampleType::Float32 || format_.type == SampleType::Float64;
    const bool isSigned = format_.type == SampleType::Int8 || format_.type == SampleType::Int16 ||
                          format_.type == SampleType::Int32;
    if (!(page == first) || !TiffPageReader::reads(page) || page.photometric > 1 ||
        page.bitsPerSample != 8 * bytesPerSample(format_.type) ||
        page.sampleFormat != (isFloat    ? 3u
                              : isSigned ? 2u
                                         : 1u) ||
        format_.channels != 1 || format_.narrowBits != 0 || page.width != format_.width ||
        page.height != format_.height)
      return nullptr;
    return &page;
  }

  void readSlice(const SliceRef& slice, std::span<std::byte> out) {
    if (const TiffPageLayout* page = multiPage_ ? readByDirectory(slice) : nullptr) {
      if (!pageReader_) pageReader_ = std::make_unique<TiffPageReader>(slice.path);
      return pageReader_->read(*page, slice.page, out);
    }
    const std::string what = describe(slice, multiPage_);
    std::unique_ptr<OIIO::ImageInput> ownInput;
    OIIO::ImageInput* in = multiPageInput_.get();
    if (!in) {
      ownInput = openImage(slice.path);
      in = ownInput.get();
    }
    OIIO::ImageSpec spec;
    if (!in->seek_subimage(slice.page, 0, spec))
      throw Error("cannot read image slice " + what + ": " + oiioError(in));
    // The file may have changed since the stack was opened.
    const SliceFormat format = sliceFormat(withFileBits(spec, *in, slice.path), in->format_name(), what);
    checkSameFormat(format_, format, describe(slices_[0], multiPage_), what);
    std::vector<std::byte> pixels(format.channels > 1 ? out.size() * format.channels : 0);
    const std::span<std::byte> read = format.channels > 1 ? std::span<std::byte>(pixels) : out;
    in->geterror();  // clears an earlier message, so that one after the read is the read's
    // A TIFF strip that cannot be read leaves zeros and an error message, but read_image succeeds.
    if (!in->read_image(slice.page, 0, 0, int(format.channels), pixelTypeOf(format.type), read.data()) ||
        in->has_error())
      throw Error("cannot read image slice " + what + ": " + firstLine(oiioError(in)));
    if (format.channels > 1) grayFromColor(pixels, format, out, what);
    if (format_.minIsWhite && spec.format == OIIO::TypeDesc::UINT8)
      for (std::byte& b : out) b = ~b;  // undoes OpenImageIO's 255 - v
    if (format_.narrowBits) narrowSamples(out, format_.type, format_.narrowBits);
  }

  std::vector<SliceRef> slices_;
  bool multiPage_ = false;
  std::unique_ptr<OIIO::ImageInput> multiPageInput_;        // kept open between slabs for multi-page TIFFs
  std::optional<std::vector<TiffPageLayout>> pageLayouts_;  // a multi-page TIFF's, where it is a TIFF
  std::unique_ptr<TiffPageReader> pageReader_;              // its pages that readByDirectory allows
  SliceFormat format_;
  VolumeInfo info_;
};

}  // namespace

int countImagePages(const std::string& path) {
  return countPages(*openImage(path), path);
}

std::unique_ptr<VolumeSource> openImageStackSource(const std::string& directoryOrPattern,
                                                   const SourceOptions& options) {
  std::vector<std::string> files = listSliceFiles(directoryOrPattern);
  const std::string numbering = sliceNumberingNote(files);
  // Slices that ImageJ saved (File > Save As > Image Sequence) keep the stack's calibration: the pixel's size
  // in the resolution tags, which an ImageJ description vouches for. A slice rarely says how far apart they
  // lie (`spacing=`); where none does, as ImageJ's own layout of a stack without it, the pixel's width.
  SourceOptions placed = options;
  std::string description = "images:" + directoryOrPattern, calibrationNote;
  if (!options.spacing && !files.empty()) {
    const auto first = openImage(files.front());
    const OIIO::ImageSpec& spec = first->spec();
    const std::string imageJ = spec.get_string_attribute("ImageDescription");
    const std::optional<TiffStackLayout> layout =
        imageJLayout(imageJ, spec.get_float_attribute("XResolution", 0.0f),
                     spec.get_float_attribute("YResolution", 0.0f), 1);
    if (layout && layout->spacing && isValidSpacing(*layout->spacing)) {
      placed.spacing = layout->spacing;
      const std::string unit = layout->unit.empty() ? "" : " " + layout->unit;
      description += " (ImageJ calibration: " + formatSpacing(*placed.spacing) + unit + ")";
      if (imageJ.find("\nspacing=") == std::string::npos)
        calibrationNote = files.front() + ": ImageJ calibrated its slices at " +
                          formatSpacing(*placed.spacing) + unit +
                          "; no slice says how far apart they lie, so their spacing is taken as the pixel's "
                          "width (--spacing gives all three)";
    }
  }
  std::vector<SliceRef> slices;
  for (auto& file : files) slices.push_back({std::move(file), 0});
  auto source =
      std::make_unique<ImageSliceSource>(std::move(slices), nullptr, std::nullopt, description, placed);
  if (!numbering.empty()) source->addNote(numbering);
  if (!calibrationNote.empty()) source->addNote(calibrationNote);
  return source;
}

std::unique_ptr<VolumeSource> openMultiPageTiffSource(const std::string& path, const SourceOptions& options) {
  auto file = openImage(path);
  // The first page's description says how ImageJ or OME-TIFF laid the pages out and how large a voxel is.
  const OIIO::ImageSpec& first = file->spec();
  const std::string firstDescription = first.get_string_attribute("ImageDescription");
  const double xResolution = first.get_float_attribute("XResolution", 0.0f);
  const double yResolution = first.get_float_attribute("YResolution", 0.0f);
  // The directories walked once: they count the pages and say how each is stored.
  std::optional<std::vector<TiffPageLayout>> pageLayouts = tiffPageLayouts(path);
  const int pages = pageLayouts ? int(pageLayouts->size()) : countPages(*file, path);
  if (pages < 2)
    throw Error(
        "openVolumeSource: " + path +
        " is a single-page TIFF; give its folder or a pattern (e.g. dir/slice_*.tif) to read a stack of "
        "slices, or a multi-page TIFF");
  std::optional<TiffStackLayout> layout = omeLayout(firstDescription, uint64_t(pages));
  if (!layout) layout = imageJLayout(firstDescription, xResolution, yResolution, uint64_t(pages));
  const std::string kind = !layout                      ? "TIFF "
                           : layout->writer == "ImageJ" ? "ImageJ hyperstack "
                                                        : "OME-TIFF image ";
  const PickedVolume picked =
      pickVolume(options,
                 layout ? VolumeCounts{layout->frames, layout->channels, "channel", layout->channelNames}
                        : VolumeCounts{},
                 kind + path);
  std::vector<SliceRef> slices;
  const uint64_t count = layout ? layout->slices : uint64_t(pages);
  for (uint64_t z = 0; z < count; ++z)
    slices.push_back({path, layout ? int(layout->page(z, picked.channel, picked.timePoint)) : int(z)});
  SourceOptions placed = options;
  if (layout && layout->spacing && !options.spacing && isValidSpacing(*layout->spacing))
    placed.spacing = layout->spacing;
  // The calibration is said where the source is: info shows it, the store keeps it.
  std::string description = "tiff:" + path;
  if (placed.spacing && !options.spacing)
    description += " (" + layout->writer + " calibration: " + formatSpacing(*placed.spacing) +
                   (layout->unit.empty() ? "" : " " + layout->unit) + ")";
  auto source = std::make_unique<ImageSliceSource>(std::move(slices), std::move(file), std::move(pageLayouts),
                                                   description, placed);
  source->describeVolume(picked);
  return source;
}

}  // namespace ropecast
