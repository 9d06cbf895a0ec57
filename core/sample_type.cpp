#include "core/sample_type.h"

#include <algorithm>
#include <cctype>
#include <string>

namespace ropecast {

std::string_view sampleTypeName(SampleType t) {
  for (const auto& [name, type] : kSampleTypeNames)  // the first name of a type is its own
    if (type == t) return name;
  return "unknown";
}

std::optional<SampleType> parseSampleType(std::string_view name) {
  std::string n(name);
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const auto& [known, type] : kSampleTypeNames)
    if (n == known) return type;
  return std::nullopt;
}

ValueMapping valueMappingFor(SampleType t, double lo, double hi) {
  switch (t) {
    case SampleType::UInt8:
    case SampleType::UInt16:
      return {1.0, 0.0};
    case SampleType::Int8:
      return {1.0, -128.0};
    case SampleType::Int16:
      return {1.0, -32768.0};
    case SampleType::UInt32:
    case SampleType::Int32:
      if (hi - lo <= 65535.0) return {1.0, lo};  // every value of the range has its own stored value
      return {(hi - lo) / 65535.0, lo};
    case SampleType::Float32:
    case SampleType::Float64: {
      const double range = hi > lo ? hi - lo : 1.0;
      return {range / 65535.0, lo};
    }
  }
  return {};
}

bool isExactMapping(SampleType t, const ValueMapping& m) {
  switch (t) {
    case SampleType::UInt8:
    case SampleType::Int8:
    case SampleType::UInt16:
    case SampleType::Int16:
      return true;
    case SampleType::UInt32:
    case SampleType::Int32:
      return m.scale == 1.0;
    case SampleType::Float32:
    case SampleType::Float64:
      return false;
  }
  return false;
}

SampleType integerTypeHolding(double lo, double hi, bool eightBitsAllowed) {
  if (eightBitsAllowed && lo >= 0 && hi <= 255) return SampleType::UInt8;
  if (eightBitsAllowed && lo >= -128 && hi <= 127) return SampleType::Int8;
  if (lo >= 0 && hi <= 65535) return SampleType::UInt16;
  if (lo >= -32768 && hi <= 32767) return SampleType::Int16;
  if (lo >= 0 && hi <= 4294967295.0) return SampleType::UInt32;
  if (lo >= -2147483648.0 && hi <= 2147483647.0) return SampleType::Int32;
  return SampleType::Float32;
}

}  // namespace ropecast
