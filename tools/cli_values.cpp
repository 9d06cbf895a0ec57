#include "tools/cli_values.h"

#include <cctype>
#include <cmath>
#include <sstream>
#include <vector>

#include "core/error.h"

namespace ropecast::tools {

namespace {

std::vector<double> parseNumbers(const std::string& text, char separator, size_t count,
                                 const std::string& option, const char* expected) {
  std::vector<double> values;
  std::stringstream in(text);
  std::string part;
  while (std::getline(in, part, separator)) {
    while (!part.empty() && std::isspace(static_cast<unsigned char>(part.back()))) part.pop_back();
    size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !std::isfinite(v))
      throw Error(option + ": expected " + expected + ", got '" + text + "'");
    values.push_back(v);
  }
  if (values.size() != count || (!text.empty() && text.back() == separator))
    throw Error(option + ": expected " + expected + ", got '" + text + "'");
  return values;
}

}  // namespace

glm::dvec3 parseTriple(const std::string& text, const std::string& option) {
  const auto v = parseNumbers(text, ',', 3, option, "three numbers X,Y,Z");
  return {v[0], v[1], v[2]};
}

glm::u32vec3 parseDims(const std::string& text, const std::string& option) {
  const auto v = parseNumbers(text, ',', 3, option, "three positive integers X,Y,Z");
  for (double d : v)
    if (d < 1 || d > 4294967295.0 || d != std::floor(d))
      throw Error(option + ": expected three positive integers X,Y,Z, got '" + text + "'");
  return {uint32_t(v[0]), uint32_t(v[1]), uint32_t(v[2])};
}

glm::u32vec2 parseImageSize(const std::string& text, const std::string& option) {
  const auto v = parseNumbers(text, 'x', 2, option, "an image size WxH such as 512x512");
  for (double d : v)
    if (d < 1 || d > 16384 || d != std::floor(d))
      throw Error(option + ": width and height must be integers in [1, 16384], got '" + text + "'");
  return {uint32_t(v[0]), uint32_t(v[1])};
}

uint64_t parseBytes(const std::string& text, const std::string& option) {
  size_t used = 0;
  double value = -1.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = text.substr(used);
  for (auto& c : unit) c = char(std::toupper(static_cast<unsigned char>(c)));
  if (unit.size() >= 2 && unit.substr(unit.size() - 2) == "IB")
    unit.resize(unit.size() - 2);
  else if (!unit.empty() && unit.back() == 'B')
    unit.pop_back();
  double scale = 1.0;
  if (unit == "K")
    scale = 1024.0;
  else if (unit == "M")
    scale = 1024.0 * 1024.0;
  else if (unit == "G")
    scale = 1024.0 * 1024.0 * 1024.0;
  else if (unit == "T")
    scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  else if (!unit.empty())
    used = 0;
  if (used == 0 || !(value >= 0.0) || !std::isfinite(value) || value * scale > 1.8e19)
    throw Error(option + ": expected a size in bytes such as 536870912, 512M or 2G, got '" + text + "'");
  return uint64_t(std::llround(value * scale));
}

}  // namespace ropecast::tools
