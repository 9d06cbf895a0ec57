// Sample types of sources and of the store, and the mapping between stored values and data units.
// Plain data and pure functions; any thread.
//
// Sources deliver samples in their own type. The store keeps uint8 or uint16 ("stored" values):
//   uint8, uint16: kept as they are;  int16: stored = value + 32768;
//   float32: quantized to 16 bits over the source's value range [lo, hi].
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

enum class SampleType : uint8_t { UInt8 = 0, UInt16 = 1, Int16 = 2, Float32 = 3 };

constexpr size_t bytesPerSample(SampleType t) {
  switch (t) {
    case SampleType::UInt8:
      return 1;
    case SampleType::UInt16:
      return 2;
    case SampleType::Int16:
      return 2;
    case SampleType::Float32:
      return 4;
  }
  return 0;
}

// The largest value of a stored type (UInt8 or UInt16): what a normalized texture value of 1 stands for.
constexpr uint32_t storedMaxOf(SampleType stored) {
  return stored == SampleType::UInt8 ? 255u : 65535u;
}

// The type the store keeps for a source type: UInt8 for UInt8, UInt16 for everything else.
constexpr SampleType storedTypeFor(SampleType source) {
  return source == SampleType::UInt8 ? SampleType::UInt8 : SampleType::UInt16;
}

// "uint8", "uint16", "int16", "float32".
std::string_view sampleTypeName(SampleType t);
// The names parseSampleType accepts (lower case; it ignores case): those above and common aliases.
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
    {"float32_t", SampleType::Float32}};
// Accepts the names of kSampleTypeNames in any case; nullopt otherwise.
std::optional<SampleType> parseSampleType(std::string_view name);

// data = stored * scale + offset.
struct ValueMapping {
  double scale = 1.0;
  double offset = 0.0;

  double toData(double stored) const { return stored * scale + offset; }
  double toStored(double data) const { return (data - offset) / scale; }
};

// The mapping the store uses for a source of type `t` whose values span [lo, hi] (lo/hi used for float32
// only).
ValueMapping valueMappingFor(SampleType t, double lo, double hi);

}  // namespace ropecast
