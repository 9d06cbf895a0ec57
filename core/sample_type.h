// Sample types of sources and of the store, and the mapping between stored values and data units.
// Plain data and pure functions; any thread.
//
// Sources deliver samples in their own type. The store keeps uint8 or uint16 ("stored" values):
//   uint8, uint16: kept as they are;  int8: stored = value + 128;  int16: stored = value + 32768;
//   uint32, int32: stored = value - lo when the source's value range [lo, hi] spans at most 65535 (exact),
//     else quantized to 16 bits over [lo, hi] as float32 is;
//   float32, float64: quantized to 16 bits over the source's value range [lo, hi].
// ValueMapping turns stored values back into data units, so isovalues and transfer functions are
// always given in the data's own units (e.g. Hounsfield), whatever the GPU texture format.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace ropecast {

enum class SampleType : uint8_t {
  UInt8 = 0,
  UInt16 = 1,
  Int16 = 2,
  Float32 = 3,
  Int8 = 4,
  UInt32 = 5,
  Int32 = 6,
  Float64 = 7,
};

constexpr size_t bytesPerSample(SampleType t) {
  switch (t) {
    case SampleType::UInt8:
    case SampleType::Int8:
      return 1;
    case SampleType::UInt16:
    case SampleType::Int16:
      return 2;
    case SampleType::UInt32:
    case SampleType::Int32:
    case SampleType::Float32:
      return 4;
    case SampleType::Float64:
      return 8;
  }
  return 0;
}

// Calls f(T{}) with T the C++ type of a sample type's values (uint8_t, int8_t, ..., double): the one place
// that maps the enum to types, for code that does the same thing to samples of every type.
template <typename F>
void forSampleType(SampleType t, F&& f) {
  switch (t) {
    case SampleType::UInt8:
      return f(uint8_t{});
    case SampleType::Int8:
      return f(int8_t{});
    case SampleType::UInt16:
      return f(uint16_t{});
    case SampleType::Int16:
      return f(int16_t{});
    case SampleType::UInt32:
      return f(uint32_t{});
    case SampleType::Int32:
      return f(int32_t{});
    case SampleType::Float32:
      return f(float{});
    case SampleType::Float64:
      return f(double{});
  }
}

// The largest value of a stored type (UInt8 or UInt16): what a normalized texture value of 1 stands for.
constexpr uint32_t storedMaxOf(SampleType stored) {
  return stored == SampleType::UInt8 ? 255u : 65535u;
}

// The type the store keeps for a source type: UInt8 for UInt8 and Int8, UInt16 for everything else.
constexpr SampleType storedTypeFor(SampleType source) {
  return source == SampleType::UInt8 || source == SampleType::Int8 ? SampleType::UInt8 : SampleType::UInt16;
}

// Whether the store's mapping for a source of type `t` depends on the source's value range [lo, hi], which
// the converter finds by a first pass over the samples when the source does not know it: float32, float64,
// uint32 and int32. (The integer types among them are kept exactly when [lo, hi] spans at most 65535.)
constexpr bool mapsOverValueRange(SampleType t) {
  switch (t) {
    case SampleType::UInt8:
    case SampleType::Int8:
    case SampleType::UInt16:
    case SampleType::Int16:
      return false;
    case SampleType::UInt32:
    case SampleType::Int32:
    case SampleType::Float32:
    case SampleType::Float64:
      return true;
  }
  return false;
}

// "uint8", "uint16", "int16", "float32", "int8", "uint32", "int32", "float64".
std::string_view sampleTypeName(SampleType t);
// The names parseSampleType accepts (lower case; it ignores case): those above and common aliases. Not
// "char": C leaves its signedness to the platform (nor is it a NRRD type name).
inline constexpr std::pair<std::string_view, SampleType> kSampleTypeNames[] = {
    {"uint8", SampleType::UInt8},
    {"u8", SampleType::UInt8},
    {"uchar", SampleType::UInt8},
    {"unsigned char", SampleType::UInt8},
    {"uint8_t", SampleType::UInt8},
    {"uint16", SampleType::UInt16},
    {"u16", SampleType::UInt16},
    {"ushort", SampleType::UInt16},
    {"unsigned short", SampleType::UInt16},
    {"uint16_t", SampleType::UInt16},
    {"int16", SampleType::Int16},
    {"i16", SampleType::Int16},
    {"short", SampleType::Int16},
    {"signed short", SampleType::Int16},
    {"int16_t", SampleType::Int16},
    {"float32", SampleType::Float32},
    {"f32", SampleType::Float32},
    {"float", SampleType::Float32},
    {"float32_t", SampleType::Float32},
    {"int8", SampleType::Int8},
    {"i8", SampleType::Int8},
    {"signed char", SampleType::Int8},
    {"int8_t", SampleType::Int8},
    {"uint32", SampleType::UInt32},
    {"u32", SampleType::UInt32},
    {"uint", SampleType::UInt32},
    {"unsigned int", SampleType::UInt32},
    {"uint32_t", SampleType::UInt32},
    {"int32", SampleType::Int32},
    {"i32", SampleType::Int32},
    {"int", SampleType::Int32},
    {"signed int", SampleType::Int32},
    {"int32_t", SampleType::Int32},
    {"float64", SampleType::Float64},
    {"f64", SampleType::Float64},
    {"double", SampleType::Float64},
    {"float64_t", SampleType::Float64}};
// The types by name, for messages that say what was expected.
inline constexpr std::string_view kSampleTypeList =
    "int8, uint8, int16, uint16, int32, uint32, float32 or float64";
// Accepts the names of kSampleTypeNames in any case; nullopt otherwise.
std::optional<SampleType> parseSampleType(std::string_view name);

// The narrowest integer type that holds every whole number in [lo, hi] (the 8-bit types only where
// `eightBitsAllowed`); Float32 where none does. For values a source rescales (DICOM's Rescale Slope and
// Intercept, NIfTI's scl_slope and scl_inter) with whole slopes and intercepts.
SampleType integerTypeHolding(double lo, double hi, bool eightBitsAllowed);

// data = stored * scale + offset.
struct ValueMapping {
  double scale = 1.0;
  double offset = 0.0;

  double toData(double stored) const { return stored * scale + offset; }
  double toStored(double data) const { return (data - offset) / scale; }
};

// The mapping the store uses for a source of type `t` whose values span [lo, hi] (lo/hi used only for the
// types of mapsOverValueRange).
ValueMapping valueMappingFor(SampleType t, double lo, double hi);

// Whether `m`, the mapping of a source of type `t`, gives every source value back exactly: always for the
// 8- and 16-bit integer types, for uint32 and int32 when their range fit 16 bits (scale 1), never for floats.
bool isExactMapping(SampleType t, const ValueMapping& m);

}  // namespace ropecast
