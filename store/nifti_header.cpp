#include "store/nifti_header.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <optional>
#include <utility>

#include "core/error.h"
#include "store/volume_source.h"

namespace ropecast {
namespace {

// Where each field lies in the two versions' headers (NIfTI-1: nifti1.h; NIfTI-2: nifti2.h).
struct NiftiLayout {
  size_t headerBytes, datatype, bitpix, dim, pixdim, voxOffset, sclSlope, sclInter, qformCode, sformCode,
      quaternB, srowX, magic, magicBytes;
  bool wide;  // NIfTI-2: 64-bit dims and offset, double floats, 32-bit codes
};

constexpr NiftiLayout kNifti1{
    kNifti1HeaderBytes, 70, 72, 40, 76, 108, 112, 116, 252, 254, 256, 280, 344, 4, false};
constexpr NiftiLayout kNifti2{
    kNifti2HeaderBytes, 12, 14, 16, 104, 168, 176, 184, 344, 348, 352, 400, 4, 8, true};

// The datatypes read, for messages.
constexpr std::string_view kNiftiTypeList =
    "uint8 (2), int16 (4), int32 (8), float32 (16), float64 (64), int8 (256), uint16 (512) or uint32 (768)";

// NIfTI's datatype codes of the sample types, read and written.
constexpr std::pair<int16_t, SampleType> kNiftiDatatypes[] = {
    {2, SampleType::UInt8},    {4, SampleType::Int16},  {8, SampleType::Int32},    {16, SampleType::Float32},
    {64, SampleType::Float64}, {256, SampleType::Int8}, {512, SampleType::UInt16}, {768, SampleType::UInt32}};

std::optional<SampleType> niftiSampleType(int64_t datatype) {
  for (const auto& [code, type] : kNiftiDatatypes)
    if (code == datatype) return type;
  return std::nullopt;
}

std::string niftiTypeName(int64_t datatype) {
  switch (datatype) {
    case 0:
      return "unknown (0)";
    case 1:
      return "binary (1)";
    case 32:
      return "complex64 (32)";
    case 128:
      return "RGB24 (128)";
    case 1024:
      return "int64 (1024)";
    case 1280:
      return "uint64 (1280)";
    case 1536:
      return "float128 (1536)";
    case 1792:
      return "complex128 (1792)";
    case 2048:
      return "complex256 (2048)";
    case 2304:
      return "RGBA32 (2304)";
    default:
      return std::to_string(datatype);
  }
}

class NiftiFields {
 public:
  NiftiFields(std::span<const std::byte> bytes, bool swapped) : bytes_(bytes), swapped_(swapped) {}

  template <typename T>
  T at(size_t offset) const {
    T value;
    std::memcpy(&value, bytes_.data() + offset, sizeof(T));
    if (!swapped_) return value;
    auto raw = std::bit_cast<std::array<std::byte, sizeof(T)>>(value);
    std::reverse(raw.begin(), raw.end());
    return std::bit_cast<T>(raw);
  }
  // A field of either version: 16-bit integers, floats and 16-bit codes in NIfTI-1; 64-bit integers, doubles
  // and 32-bit codes in NIfTI-2 (`wide`).
  int64_t integer(size_t offset, bool wide) const { return wide ? at<int64_t>(offset) : at<int16_t>(offset); }
  double real(size_t offset, bool wide) const { return wide ? at<double>(offset) : at<float>(offset); }
  int32_t code(size_t offset, bool wide) const { return wide ? at<int32_t>(offset) : at<int16_t>(offset); }

 private:
  std::span<const std::byte> bytes_;
  bool swapped_;
};

// A point of NIfTI's RAS in LPS; nullopt unless finite.
std::optional<glm::dvec3> lpsOrigin(glm::dvec3 ras) {
  if (!std::isfinite(ras.x) || !std::isfinite(ras.y) || !std::isfinite(ras.z)) return std::nullopt;
  return glm::dvec3(-ras.x, -ras.y, ras.z);
}

}  // namespace

int16_t niftiDatatypeOf(SampleType type) {
  for (const auto& [code, known] : kNiftiDatatypes)
    if (known == type) return code;
  return 0;
}

NiftiHeader parseNiftiHeader(std::span<const std::byte> bytes, const std::string& fileName,
                             bool analyzeAllowed) {
  const auto fail = [&](const std::string& what) -> Error {
    return Error("NIfTI header of " + fileName + ": " + what);
  };
  if (bytes.size() < kNifti1HeaderBytes)
    throw fail("the file ends after " + std::to_string(bytes.size()) + " bytes, within the " +
               std::to_string(kNifti1HeaderBytes) + " bytes of a NIfTI-1 header");
  int32_t sizeofHdr;
  std::memcpy(&sizeofHdr, bytes.data(), 4);
  const int32_t swappedSize = int32_t(__builtin_bswap32(uint32_t(sizeofHdr)));
  const bool swapped = sizeofHdr != 348 && sizeofHdr != 540;
  const int32_t size = swapped ? swappedSize : sizeofHdr;
  if (size != 348 && size != 540)
    throw fail("sizeof_hdr is " + std::to_string(sizeofHdr) +
               "; expected 348 (NIfTI-1) or 540 (NIfTI-2): not a NIfTI file");
  const NiftiLayout& layout = size == 348 ? kNifti1 : kNifti2;
  if (bytes.size() < layout.headerBytes)
    throw fail("the file ends after " + std::to_string(bytes.size()) + " bytes, within the " +
               std::to_string(kNifti2HeaderBytes) + " bytes of a NIfTI-2 header");
  // The file's byte order is the one in which sizeof_hdr reads 348 or 540.
  const NiftiFields field(bytes, swapped);

  NiftiHeader header;
  header.version = layout.wide ? 2 : 1;
  header.bigEndian = swapped == (std::endian::native == std::endian::little);
  const char* magic = reinterpret_cast<const char*>(bytes.data() + layout.magic);
  const std::string_view single =
      layout.wide ? std::string_view("n+2\0\r\n\032\n", 8) : std::string_view("n+1\0", 4);
  const std::string_view paired =
      layout.wide ? std::string_view("ni2\0\r\n\032\n", 8) : std::string_view("ni1\0", 4);
  const std::string_view found(magic, layout.magicBytes);
  if (found == paired) {
    header.pairedFile = true;
  } else if (!layout.wide && analyzeAllowed && found != single) {
    header.pairedFile = header.analyze = true;  // where NIfTI has its magic, ANALYZE keeps hist.smin
  } else if (found != single) {
    throw fail("magic is not '" + std::string(single.substr(0, 3)) + "' or '" +
               std::string(paired.substr(0, 3)) +
               "' (an ANALYZE 7.5 header is read as the .hdr of a .hdr and .img pair), not a NIfTI file");
  }

  const int64_t rank = field.integer(layout.dim, layout.wide);
  if (rank < 3 || rank > 7)
    throw fail("dim[0] is " + std::to_string(rank) +
               "; expected 3 to 7 dimensions (a volume, or volumes of time "
               "points and components)");
  uint64_t total = 8;  // widest sample
  for (int axis = 0; axis < 3; ++axis) {
    const int64_t n = field.integer(layout.dim + size_t(axis + 1) * (layout.wide ? 8 : 2), layout.wide);
    if (n < 1 || n > int64_t(UINT32_MAX))
      throw fail("dim[" + std::to_string(axis + 1) + "] is " + std::to_string(n) +
                 "; expected a positive size below 2^32");
    header.sizes[axis] = uint32_t(n);
    if (total > (uint64_t(1) << 62) / uint64_t(n))
      throw fail("dims are too large (more than 2^62 bytes of data)");
    total *= uint64_t(n);
  }
  uint64_t* const volumeCounts[] = {&header.timePoints, &header.components, &header.components,
                                    &header.components};
  for (int64_t axis = 4; axis <= rank; ++axis) {
    const int64_t n = field.integer(layout.dim + size_t(axis) * (layout.wide ? 8 : 2), layout.wide);
    if (n < 1 || n > int64_t(UINT32_MAX))
      throw fail("dim[" + std::to_string(axis) + "] is " + std::to_string(n) +
                 "; expected a positive size below 2^32");
    if (total > (uint64_t(1) << 62) / uint64_t(n))
      throw fail("dims are too large (more than 2^62 bytes of data)");
    total *= uint64_t(n);
    *volumeCounts[axis - 4] *= uint64_t(n);
  }

  const int64_t datatype = field.code(layout.datatype, false);
  const auto type = niftiSampleType(datatype);
  if (!type)
    throw fail("datatype " + niftiTypeName(datatype) + " is not supported; expected " +
               std::string(kNiftiTypeList));
  header.type = *type;
  const int64_t bitpix = field.code(layout.bitpix, false);
  if (bitpix != int64_t(8 * bytesPerSample(header.type)))
    throw fail("bitpix is " + std::to_string(bitpix) + ", but datatype " + std::to_string(datatype) +
               " has " + std::to_string(8 * bytesPerSample(header.type)) + "-bit samples");

  for (int axis = 0; axis < 3; ++axis) {
    const double d = field.real(layout.pixdim + size_t(axis + 1) * (layout.wide ? 8 : 4), layout.wide);
    if (std::isfinite(d) && d != 0.0)
      header.spacing[axis] = std::abs(d);
    else
      header.spacingUnknown = true;
  }

  const double voxOffset =
      layout.wide ? double(field.at<int64_t>(layout.voxOffset)) : double(field.at<float>(layout.voxOffset));
  if (!(voxOffset >= 0.0) || voxOffset > 0x1p40 || voxOffset != std::floor(voxOffset))
    throw fail("vox_offset " + formatNumber(voxOffset) + " is not a byte offset");
  header.voxOffset = uint64_t(voxOffset);
  if (!header.pairedFile && header.voxOffset < layout.headerBytes)
    throw fail("vox_offset " + std::to_string(header.voxOffset) + " lies within the " +
               std::to_string(layout.headerBytes) + "-byte header");

  const double slope = field.real(layout.sclSlope, layout.wide);
  const double intercept = field.real(layout.sclInter, layout.wide);
  if (std::isfinite(slope) && slope != 0.0) {
    header.slope = slope;
    header.intercept = std::isfinite(intercept) ? intercept : 0.0;
    header.scaled = !(header.slope == 1.0 && header.intercept == 0.0);
    if (!header.scaled) header.slope = 1.0;
  }

  if (header.analyze) return header;
  // The sform where its code is set (NIfTI's method 3), else the qform (method 2); neither: axes as stored.
  const size_t real = layout.wide ? 8 : 4;
  if (field.code(layout.sformCode, layout.wide) > 0) {
    std::array<double, 9> m{};  // rows srow_x, srow_y, srow_z; column a is axis a's vector
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        m[size_t(r * 3 + c)] = field.real(layout.srowX + size_t(r * 4 + c) * real, layout.wide);
    const std::optional<AxisDirections> axes =
        axisDirectionsOf({m[0], m[3], m[6]}, {m[1], m[4], m[7]}, {m[2], m[5], m[8]});
    if (axes) {
      header.axes = rasToLps(*axes);
      header.origin = lpsOrigin({field.real(layout.srowX + 3 * real, layout.wide),
                                 field.real(layout.srowX + 7 * real, layout.wide),
                                 field.real(layout.srowX + 11 * real, layout.wide)});
    } else {
      header.transformNotApplied = true;
      const auto lps = [](glm::dvec3 ras) { return glm::dvec3(-ras.x, -ras.y, ras.z); };
      const std::optional<glm::dvec3> offset = lpsOrigin({field.real(layout.srowX + 3 * real, layout.wide),
                                                          field.real(layout.srowX + 7 * real, layout.wide),
                                                          field.real(layout.srowX + 11 * real, layout.wide)});
      bool finite = offset.has_value();
      for (const double v : m) finite = finite && std::isfinite(v);
      if (finite)
        header.shearedSform = {lps({m[0], m[3], m[6]}), lps({m[1], m[4], m[7]}), lps({m[2], m[5], m[8]}),
                               *offset};
    }
  } else if (field.code(layout.qformCode, layout.wide) > 0) {
    // The rotation of the unit quaternion (a, b, c, d), a = sqrt(1 - b^2 - c^2 - d^2), as the NIfTI-1
    // header's comments give it; pixdim[0] = -1 (qfac) turns the third axis around.
    const double b = field.real(layout.quaternB, layout.wide),
                 c = field.real(layout.quaternB + real, layout.wide),
                 d = field.real(layout.quaternB + 2 * real, layout.wide);
    const double a = std::sqrt(std::max(0.0, 1.0 - (b * b + c * c + d * d)));
    const double qfac = field.real(layout.pixdim, layout.wide) < 0.0 ? -1.0 : 1.0;
    const glm::dvec3 x(a * a + b * b - c * c - d * d, 2 * (b * c + a * d), 2 * (b * d - a * c));
    const glm::dvec3 y(2 * (b * c - a * d), a * a + c * c - b * b - d * d, 2 * (c * d + a * b));
    const glm::dvec3 z(2 * (b * d + a * c), 2 * (c * d - a * b), a * a + d * d - c * c - b * b);
    const std::optional<AxisDirections> axes = axisDirectionsOf(x, y, qfac * z);
    if (axes) {
      header.axes = rasToLps(*axes);
      // qoffset_x, _y, _z follow quatern_d.
      header.origin = lpsOrigin({field.real(layout.quaternB + 3 * real, layout.wide),
                                 field.real(layout.quaternB + 4 * real, layout.wide),
                                 field.real(layout.quaternB + 5 * real, layout.wide)});
    } else {
      header.transformNotApplied = true;  // b, c, d not finite
    }
  }
  return header;
}

}  // namespace ropecast
