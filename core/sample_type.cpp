#include "core/sample_type.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace ropecast {

std::string_view sampleTypeName(SampleType t) {
  switch (t) {
    case SampleType::UInt8:
      return "uint8";
    case SampleType::UInt16:
      return "uint16";
    case SampleType::Int16:
      return "int16";
    case SampleType::Float32:
      return "float32";
  }
  return "unknown";
}

std::optional<SampleType> parseSampleType(std::string_view name) {
  std::string n(name);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  if (n == "uint8" || n == "u8" || n == "uchar" || n == "unsigned char" || n == "uint8_t")
    return SampleType::UInt8;
  if (n == "uint16" || n == "u16" || n == "ushort" || n == "unsigned short" || n == "uint16_t")
    return SampleType::UInt16;
  if (n == "int16" || n == "i16" || n == "short" || n == "signed short" || n == "int16_t")
    return SampleType::Int16;
  if (n == "float32" || n == "f32" || n == "float" || n == "float32_t") return SampleType::Float32;
  return std::nullopt;
}

ValueMapping valueMappingFor(SampleType t, double lo, double hi) {
  switch (t) {
    case SampleType::UInt8:
    case SampleType::UInt16:
      return {1.0, 0.0};
    case SampleType::Int16:
      return {1.0, -32768.0};
    case SampleType::Float32: {
      const double range = hi > lo ? hi - lo : 1.0;
      return {range / 65535.0, lo};
    }
  }
  return {};
}

}  // namespace ropecast
