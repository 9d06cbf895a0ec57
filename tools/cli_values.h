// Options with compound or enumerated values ("X,Y,Z", "WxH", "512M", "iso|dvr"), shared by every subcommand.
// CLI11 parses and checks them while it reads the command line, before any work starts: --help lists the
// accepted forms, and a bad value ends the run with CLI11's message naming the option (exit status 2, a usage
// error). Main thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

namespace ropecast::tools {

// "1.5,2,3" -> three finite numbers (CLI11 also takes them as three arguments, "1.5 2 3"). --help shows
// "FLOAT x 3"; the help text names the fields ("X,Y,Z") and any default.
CLI::Option* addTripleOption(CLI::App& app, const std::string& name, std::vector<double>& xyz,
                             const std::string& help);
// The same, each number in [lo, hi].
CLI::Option* addTripleOptionIn(CLI::App& app, const std::string& name, std::vector<double>& xyz,
                               const std::string& help, double lo, double hi);
// "LO,HI" -> two finite numbers (their order is the caller's to check).
CLI::Option* addRangeOption(CLI::App& app, const std::string& name, std::vector<double>& values,
                            const std::string& help);
// "X,Y,Z,NX,NY,NZ" -> six finite numbers (a plane: a point and a normal).
CLI::Option* addPlaneOption(CLI::App& app, const std::string& name, std::vector<double>& values,
                            const std::string& help);
// "KA,KD,KS,SHININESS" -> four finite numbers in [0, 1024] (a material; the caller checks each field's own
// range: materialProblem).
CLI::Option* addMaterialOption(CLI::App& app, const std::string& name, std::vector<double>& values,
                               const std::string& help);
// What is wrong with a material (ambient, diffuse and specular in [0, 1], shininess in [1, 1024]) named
// `name`, or "".
std::string materialProblem(const std::string& name, const std::vector<double>& values);
// "301,370,316" -> three integers in [1, 2^32 - 1].
CLI::Option* addDimsOption(CLI::App& app, const std::string& name, std::vector<uint32_t>& xyz,
                           const std::string& help);
// "512x512" -> width and height, each an integer in [1, 16384].
CLI::Option* addImageSizeOption(CLI::App& app, const std::string& name, std::vector<uint32_t>& wh,
                                const std::string& help);
// "1073741824", "512M", "2G", "64K", "1.5G" (binary units, optional "iB"/"B", any case) -> bytes.
CLI::Option* addByteSizeOption(CLI::App& app, const std::string& name, uint64_t& bytes,
                               const std::string& help);

// "A:B", "A:", ":B" or ":": voxel indices A to B - 1 along one axis, half-open as Python's slices, a bound
// left out being the volume's edge. nullopt for anything else, or when A >= B.
struct VoxelRange {
  std::optional<uint64_t> begin, end;
};
std::optional<VoxelRange> parseVoxelRange(std::string_view text);
// "X0:X1,Y0:Y1,Z0:Z1" as its three ranges, each one parseVoxelRange takes; nullopt otherwise.
std::optional<std::vector<std::string>> splitVoxelRanges(std::string_view text);
// The voxels [begin, end) per axis that three such ranges name in a volume of `dims`. Throws UsageError
// naming `option` ("--crop"), the axis and the extent (`whose` voxels: "the volume's", "level 2's") when a
// range does not lie in it.
struct VoxelBox {
  glm::u32vec3 begin{0}, end{0};
};
VoxelBox voxelBoxOf(const std::string& option, const std::vector<std::string>& ranges, glm::u32vec3 dims,
                    const std::string& whose = "the volume's");
// "X0:X1,Y0:Y1,Z0:Z1": three such ranges (--crop). Whether they lie in the volume is the caller's check,
// once the volume is open.
CLI::Option* addVoxelRangesOption(CLI::App& app, const std::string& name, std::vector<std::string>& ranges,
                                  const std::string& help);

// The value of a parsed triple (addTripleOption guarantees three numbers).
inline glm::dvec3 toVec3(const std::vector<double>& xyz) {
  return {xyz.at(0), xyz.at(1), xyz.at(2)};
}
// "1,0.5,2" as a message shows a triple.
std::string formatTriple(const std::vector<double>& xyz);

// The CLI11 transform of addByteSizeOption: rewrites a size to its byte count, or returns what was expected.
CLI::Validator byteSize();
// A check after byteSize() that refuses a size of 0 bytes; `instead` says what the user may want ("leave
// --gpu-budget out for the driver's default").
CLI::Validator nonZeroSize(const std::string& instead);
// The CLI11 transform of integer options given as numbers ("512", "5e2", "512.0"): rewrites the value to the
// integer's digits, or returns what was expected.
CLI::Validator integerIn(double lo, double hi);
// integerIn for an option of one integer, with the range in --help ("UINT in [1, 1000000]"). (CLI::Range says
// "Value 2.5 not in range 1 to 1000000", and the same of 2e1.)
CLI::Validator integerRange(double lo, double hi);

// "a", "a or b", "a, b or c".
std::string alternatives(const std::vector<std::string>& names);

// `check` with its refusal said as "expected EXPECTED, got 'VALUE'" (CLI::IsMember says "foo not in
// {iso,dvr}"); a value `check` maps (CLI::ignore_case) stays mapped.
CLI::Validator expecting(CLI::Validator check, const std::string& expected);

// CLI::IsMember(values): "expected 8, 16, 32 or 64, got '7'".
template <typename T>
CLI::Validator oneOf(const std::vector<T>& values) {
  std::vector<std::string> names;
  for (const T& value : values) names.push_back(CLI::detail::to_string(value));
  return expecting(CLI::IsMember(values), alternatives(names));
}

// An option naming one value of an enum: CLI::IsMember checks the name (--help lists the names, a bad one is
// refused with them) and CLI::Transformer maps it straight to the enum. (CLI::CheckedTransformer alone would
// also take the enum's underlying integers, "--mode 1", and list them in --help.) `Target` is the enum or an
// std::optional of it; `listed` replaces the list of names in --help when aliases would crowd it.
template <typename Enum, typename Target>
CLI::Option* addEnumOption(CLI::App& app, const std::string& name, Target& value,
                           const std::vector<std::pair<std::string, Enum>>& names, const std::string& help,
                           bool ignoreCase = false, const std::string& listed = "") {
  std::vector<std::string> keys;
  for (const auto& entry : names) keys.push_back(entry.first);
  CLI::Validator member = expecting(ignoreCase ? CLI::IsMember(keys, CLI::ignore_case) : CLI::IsMember(keys),
                                    listed.empty() ? alternatives(keys) : listed);
  if (!listed.empty()) member.description(listed);
  // transform() puts a validator first: the name is checked, then mapped.
  CLI::Option* option = app.add_option(name, value, help)
                            ->transform(CLI::Transformer(names).description(""))
                            ->transform(member);
  if constexpr (std::is_same_v<Target, Enum>) {
    for (const auto& entry : names)
      if (entry.second == value) {
        option->default_str(entry.first);
        break;
      }
  }
  return option;
}

}  // namespace ropecast::tools
