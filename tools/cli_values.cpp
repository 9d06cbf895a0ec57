#include "tools/cli_values.h"

#include <cctype>
#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "core/header_text.h"
#include "core/number_text.h"
#include "store/volume_source.h"
#include "tools/cli_checks.h"

namespace ropecast::tools {

namespace {
// CLI11 splits "1, 2 ,3" at the delimiter but leaves the blanks, which its number conversion refuses.
std::string trimmed(std::string text) {
  return CLI::detail::trim_copy(text);
}

// COUNT values separated by DELIMITER, each trimmed, then converted by `check`.
template <typename T>
CLI::Option* addListOption(CLI::App& app, const std::string& name, std::vector<T>& values,
                           const std::string& help, char delimiter, int count, const char* typeName,
                           const CLI::Validator& check) {
  return app.add_option(name, values, help)
      ->delimiter(delimiter)
      ->expected(count)
      ->type_name(typeName)
      ->transform(check)
      ->transform(trimmed);
}
}  // namespace

CLI::Option* addTripleOption(CLI::App& app, const std::string& name, std::vector<double>& xyz,
                             const std::string& help) {
  return addTripleOptionIn(app, name, xyz, help, -HUGE_VAL, HUGE_VAL);
}

CLI::Option* addTripleOptionIn(CLI::App& app, const std::string& name, std::vector<double>& xyz,
                               const std::string& help, double lo, double hi) {
  return addListOption(app, name, xyz, help, ',', 3, "FLOAT", finiteIn(lo, hi));
}

CLI::Option* addRangeOption(CLI::App& app, const std::string& name, std::vector<double>& values,
                            const std::string& help) {
  return addListOption(app, name, values, help, ',', 2, "FLOAT", finiteIn(-HUGE_VAL, HUGE_VAL));
}

CLI::Option* addPlaneOption(CLI::App& app, const std::string& name, std::vector<double>& values,
                            const std::string& help) {
  return addListOption(app, name, values, help, ',', 6, "FLOAT", finiteIn(-HUGE_VAL, HUGE_VAL));
}

CLI::Option* addMaterialOption(CLI::App& app, const std::string& name, std::vector<double>& values,
                               const std::string& help) {
  return addListOption(app, name, values, help, ',', 4, "FLOAT", finiteIn(0.0, 1024.0));
}

std::string materialProblem(const std::string& name, const std::vector<double>& values) {
  if (values.size() != 4) return name + ": expected four numbers KA,KD,KS,SHININESS";
  const char* fields[] = {"KA", "KD", "KS"};
  for (size_t i = 0; i < 3; ++i)
    if (!(values[i] >= 0.0 && values[i] <= 1.0))
      return name + ": " + fields[i] + " must lie in [0, 1], got " + formatNumber(values[i]);
  if (!(values[3] >= 1.0 && values[3] <= 1024.0))
    return name + ": SHININESS must lie in [1, 1024], got " + formatNumber(values[3]);
  return "";
}

CLI::Option* addDimsOption(CLI::App& app, const std::string& name, std::vector<uint32_t>& xyz,
                           const std::string& help) {
  return addListOption(app, name, xyz, help, ',', 3, "UINT", integerIn(1, kMaxDimsPerAxis));
}

std::optional<VoxelRange> parseVoxelRange(std::string_view text) {
  const size_t colon = text.find(':');
  if (colon == std::string_view::npos) return std::nullopt;
  const auto bound = [](std::string_view digits, std::optional<uint64_t>& value) {
    digits = trimBlanks(digits);
    if (digits.empty()) return true;
    if (digits.front() == '+' || digits.front() == '-') return false;
    value = parseWholeNumber<uint64_t>(digits);
    return value.has_value();
  };
  VoxelRange range;
  if (!bound(text.substr(0, colon), range.begin) || !bound(text.substr(colon + 1), range.end))
    return std::nullopt;
  if (range.begin && range.end && !(*range.begin < *range.end)) return std::nullopt;
  return range;
}

std::optional<std::vector<std::string>> splitVoxelRanges(std::string_view text) {
  std::vector<std::string> ranges;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    ranges.emplace_back(
        trimBlanks(text.substr(start, comma == std::string_view::npos ? comma : comma - start)));
    if (!parseVoxelRange(ranges.back()) || ranges.size() > 3) return std::nullopt;
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (ranges.size() != 3) return std::nullopt;
  return ranges;
}

VoxelBox voxelBoxOf(const std::string& option, const std::vector<std::string>& ranges, glm::u32vec3 dims,
                    const std::string& whose) {
  if (ranges.size() != 3) throw UsageError(option + ": expected three ranges X0:X1,Y0:Y1,Z0:Z1");
  VoxelBox box;
  for (int axis = 0; axis < 3; ++axis) {
    const std::optional<VoxelRange> range = parseVoxelRange(ranges[axis]);
    const uint64_t n = dims[axis];
    const uint64_t begin = range ? range->begin.value_or(0) : 0, end = range ? range->end.value_or(n) : 0;
    const std::string name(1, "xyz"[axis]);
    if (!range || !(begin < end) || end > n)
      throw UsageError(option + ": the " + name + " range " + ranges[axis] + " does not lie in " + whose +
                       " voxels 0:" + std::to_string(n) + " along " + name + " (" + formatDims(dims) + ")");
    box.begin[axis] = uint32_t(begin);
    box.end[axis] = uint32_t(end);
  }
  return box;
}

CLI::Option* addVoxelRangesOption(CLI::App& app, const std::string& name, std::vector<std::string>& ranges,
                                  const std::string& help) {
  const CLI::Validator range(
      [](std::string& input) -> std::string {
        return parseVoxelRange(input) ? ""
                                      : "expected a range of voxels A:B with A < B (A: or :B to the volume's "
                                        "edge, : for the whole axis), got '" +
                                            input + "'";
      },
      "", "voxelRange");
  return addListOption(app, name, ranges, help, ',', 3, "A:B", range);
}

CLI::Option* addImageSizeOption(CLI::App& app, const std::string& name, std::vector<uint32_t>& wh,
                                const std::string& help) {
  return addListOption(app, name, wh, help, 'x', 2, "UINT", integerIn(1, 16384));
}

CLI::Option* addByteSizeOption(CLI::App& app, const std::string& name, uint64_t& bytes,
                               const std::string& help) {
  return app.add_option(name, bytes, help)->type_name("BYTES")->transform(byteSize());
}

std::string formatTriple(const std::vector<double>& xyz) {
  std::string text;
  for (double v : xyz) text += (text.empty() ? "" : ",") + formatNumber(v);
  return text;
}

CLI::Validator nonZeroSize(const std::string& instead) {
  return CLI::Validator(
      [instead](std::string& input) -> std::string {
        return input == "0" ? "expected a size above 0 bytes (" + instead + "), got 0" : "";
      },
      "", "nonZeroSize");
}

CLI::Validator integerIn(double lo, double hi) {
  // Integers in full (%g would print 1048576 as 1.04858e+06).
  const auto integer = [](double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.0f", v);
    return std::string(text);
  };
  const std::string range = "[" + integer(lo) + ", " + integer(hi) + "]";
  return CLI::Validator(
      [lo, hi, range](std::string& input) -> std::string {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(input, v) || !std::isfinite(v) || v != std::floor(v) || v < lo ||
            v > hi)
          return "expected an integer in " + range + ", got '" + input + "'";
        input = std::to_string(uint64_t(v));
        return "";
      },
      "", "integerIn");
}

CLI::Validator integerRange(double lo, double hi) {
  CLI::Validator integer = integerIn(lo, hi);
  char range[96];
  std::snprintf(range, sizeof range, "%s in [%.0f, %.0f]", lo < 0 ? "INT" : "UINT", lo, hi);
  return integer.description(range);
}

std::string alternatives(const std::vector<std::string>& names) {
  std::string text;
  for (size_t i = 0; i < names.size(); ++i)
    text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
  return text;
}

CLI::Validator expecting(CLI::Validator check, const std::string& expected) {
  const std::string description = check.get_description();
  return CLI::Validator(
      [check = std::move(check), expected](std::string& input) -> std::string {
        const std::string given = input;
        return check(input).empty() ? "" : "expected " + expected + ", got '" + given + "'";
      },
      description, "expecting");
}

// Not CLI::AsSizeValue: it reads the number as an integer ("1.5G" is refused), takes a bare unit ("M" as
// 1 MiB) and wraps a negative number ("-1G" overflows from 2^64 - 1). This keeps the sizes ropecast has
// always accepted: a non-negative decimal number, then nothing or K, M, G, T with an optional "B" or "iB", in
// any case, all binary (1K = 1024).
CLI::Validator byteSize() {
  return CLI::Validator(
      [](std::string& input) -> std::string {
        size_t used = 0;
        double value = -1.0;
        try {
          value = std::stod(input, &used);
        } catch (const std::exception&) {
          used = 0;
        }
        std::string unit = input.substr(used);
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
          return "expected a size in bytes such as 536870912, 512M or 2G (binary units: 1K = 1024), got '" +
                 input + "'";
        input = std::to_string(uint64_t(std::round(value * scale)));  // < 1.8e19 < 2^64
        return "";
      },
      "", "byteSize");
}

}  // namespace ropecast::tools
