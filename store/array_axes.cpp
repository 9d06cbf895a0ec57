#include "store/array_axes.h"

#include <algorithm>

namespace ropecast {
namespace {

std::string emptyProblem(std::span<const uint64_t> extent, const std::array<int, 3>& zyx) {
  for (int a : zyx)
    if (extent[size_t(a)] == 0) return "it is empty (" + formatExtent(extent) + ")";
  return "";
}

}  // namespace

std::string formatExtent(std::span<const uint64_t> extent) {
  std::string text;
  for (uint64_t n : extent) {
    if (!text.empty()) text += 'x';
    text += std::to_string(n);
  }
  return text.empty() ? "a scalar" : text;
}

ArrayAxes volumeAxes(std::span<const uint64_t> extent) {
  ArrayAxes axes;
  const int rank = int(extent.size());
  if (rank < 3) {
    axes.problem = "it has " + std::to_string(rank) + (rank == 1 ? " axis" : " axes") + " (" +
                   formatExtent(extent) + "); a volume has three";
    return axes;
  }
  std::vector<int> chosen;
  for (int a = 0; a < rank; ++a)
    if (extent[size_t(a)] != 1) chosen.push_back(a);
  if (chosen.size() > 3) {
    axes.problem = "it has " + std::to_string(chosen.size()) + " axes longer than 1 (" +
                   formatExtent(extent) +
                   ") and does not name them: name them with --axes, slowest first (e.g. --axes tzyx for a "
                   "time series, czyx for channels; one volume of t and c is read)";
    return axes;
  }
  if (rank == 3) chosen = {0, 1, 2};
  while (chosen.size() < 3) {
    int pad = (chosen.empty() ? rank : chosen.front()) - 1;
    if (pad < 0)
      for (pad = 0; std::find(chosen.begin(), chosen.end(), pad) != chosen.end();) ++pad;
    chosen.push_back(pad);
    std::sort(chosen.begin(), chosen.end());
  }
  axes.zyx = {chosen[0], chosen[1], chosen[2]};
  axes.problem = emptyProblem(extent, axes.zyx);
  return axes;
}

ArrayAxes volumeAxesNamed(std::span<const uint64_t> extent, const std::vector<std::string>& names) {
  ArrayAxes axes;
  if (names.size() != extent.size()) {
    axes.problem = "it names " + std::to_string(names.size()) + " axes for " + std::to_string(extent.size());
    return axes;
  }
  const char* wanted[] = {"z", "y", "x"};
  for (int i = 0; i < 3; ++i) {
    const auto at = std::find(names.begin(), names.end(), wanted[i]);
    if (at == names.end()) {
      axes.problem = std::string("it has no axis named ") + wanted[i];
      return axes;
    }
    axes.zyx[size_t(i)] = int(at - names.begin());
  }
  for (size_t a = 0; a < names.size(); ++a) {
    int* const picked = names[a] == "t" ? &axes.time : names[a] == "c" ? &axes.channel : nullptr;
    if (picked && *picked < 0) {
      *picked = int(a);
    } else if (names[a] != "z" && names[a] != "y" && names[a] != "x" && extent[a] != 1) {
      axes.problem = "its axis " + names[a] + " has " + std::to_string(extent[a]) + " entries (" +
                     formatExtent(extent) +
                     "); besides z, y and x only axes named t (time) and c (channel) may be longer, one "
                     "volume of them read";
      return axes;
    }
  }
  axes.problem = emptyProblem(extent, axes.zyx);
  return axes;
}

GivenAxisNames axisNamesOf(const std::string& letters) {
  GivenAxisNames given;
  for (const char letter : letters) {
    if (std::string("tczyx").find(letter) == std::string::npos) {
      given.problem = "'" + std::string(1, letter) + "' is not an axis: expected t, c, z, y or x for each";
      return given;
    }
    if (std::find(given.names.begin(), given.names.end(), std::string(1, letter)) != given.names.end()) {
      given.problem = "'" + std::string(1, letter) + "' is named twice";
      return given;
    }
    given.names.emplace_back(1, letter);
  }
  for (const char* wanted : {"z", "y", "x"})
    if (std::find(given.names.begin(), given.names.end(), wanted) == given.names.end())
      given.problem = std::string("no axis is named ") + wanted + " (z, y and x are needed)";
  return given;
}

ArrayAxes arrayAxesOf(std::span<const uint64_t> extent, const std::vector<std::string>& names,
                      const std::string& given) {
  if (given.empty()) return names.empty() ? volumeAxes(extent) : volumeAxesNamed(extent, names);
  ArrayAxes axes;
  if (!names.empty()) {
    std::string named;
    for (const std::string& name : names) named += (named.empty() ? "" : ", ") + name;
    axes.problem = "it names its axes itself (" + named + "); --axes is for arrays that do not";
    return axes;
  }
  const GivenAxisNames letters = axisNamesOf(given);
  if (!letters.problem.empty()) {
    axes.problem = "--axes " + given + ": " + letters.problem;
    return axes;
  }
  if (letters.names.size() != extent.size()) {
    axes.problem = "--axes " + given + " names " + std::to_string(letters.names.size()) + " axes; it has " +
                   std::to_string(extent.size()) + " (" + formatExtent(extent) + ")";
    return axes;
  }
  return volumeAxesNamed(extent, letters.names);
}

}  // namespace ropecast
