#include "tools/regress_suite.h"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <set>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/file_names.h"
#include "core/input_file.h"
#include "core/json_keys.h"
#include "store/procedural.h"

namespace ropecast::tools {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Reads the tolerances in `object` over `base`; every key must be known, every value a finite number in
// range.
RegressTolerances readTolerances(const json& object, RegressTolerances base, const std::string& where) {
  if (!object.is_object()) throw SuiteError(where + ": expected an object of tolerances");
  for (const auto& [key, value] : object.items()) {
    double* target = key == "min_psnr_db"           ? &base.minPsnrDb
                     : key == "max_pixel_error"     ? &base.maxPixelError
                     : key == "failing_pixel_error" ? &base.failingPixelError
                     : key == "max_failing_share"   ? &base.maxFailingShare
                                                    : nullptr;
    if (!target)
      throw SuiteError(where + ": unknown tolerance '" + key +
                       "' (expected min_psnr_db, max_pixel_error, failing_pixel_error, max_failing_share)");
    if (!value.is_number() || !std::isfinite(value.get<double>()))
      throw SuiteError(where + "." + key + ": expected a finite number, got " + value.dump());
    const double v = value.get<double>();
    const bool inUnitRange = key != "min_psnr_db";
    if (v < 0.0 || (inUnitRange && v > 1.0))
      throw SuiteError(where + "." + key + ": expected a number in " + (inUnitRange ? "[0, 1]" : "[0, inf)") +
                       ", got " + value.dump());
    *target = v;
  }
  return base;
}

std::string requireString(const json& object, const char* key, const std::string& where) {
  const auto it = object.find(key);
  if (it == object.end()) throw SuiteError(where + ": missing \"" + key + "\"");
  if (!it->is_string() || it->get<std::string>().empty())
    throw SuiteError(where + "." + key + ": expected a non-empty string, got " + it->dump());
  return it->get<std::string>();
}

bool isPlainName(const std::string& name) {
  for (const char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-' && c != '.') return false;
  return !name.empty() && name.front() != '.';
}

}  // namespace

RegressSuite parseRegressSuite(const std::string& text, const std::string& suitePath) {
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    throw SuiteError(suitePath + ": not valid JSON: " + e.what());
  }
  if (const std::string key = duplicateJsonKey(text); !key.empty())
    throw SuiteError(suitePath + ": the key \"" + key +
                     "\" is given twice in one object (only the last would count)");
  if (!root.is_object()) throw SuiteError(suitePath + ": expected an object {\"cases\": [...]}");
  RegressTolerances defaults;
  for (const auto& [key, value] : root.items()) {
    if (key == "tolerances")
      defaults = readTolerances(value, defaults, suitePath + ": tolerances");
    else if (key != "cases" && key != "description")
      throw SuiteError(suitePath + ": unknown key '" + key + "' (expected cases, tolerances, description)");
  }
  const auto cases = root.find("cases");
  if (cases == root.end() || !cases->is_array() || cases->empty())
    throw SuiteError(suitePath + ": expected \"cases\": a non-empty array of cases");

  const fs::path folder = fs::path(suitePath).parent_path();
  const auto resolve = [&folder](const std::string& path) {
    return fs::path(path).is_absolute() ? path : (folder / path).lexically_normal().string();
  };
  RegressSuite suite;
  suite.path = suitePath;
  std::set<std::string> names;
  for (size_t i = 0; i < cases->size(); ++i) {
    const json& entry = (*cases)[i];
    std::string where = suitePath + ": cases[" + std::to_string(i) + "]";
    if (!entry.is_object()) throw SuiteError(where + ": expected an object");
    RegressCase c;
    c.name = requireString(entry, "name", where);
    if (!isPlainName(c.name))
      throw SuiteError(where + ".name: '" + c.name +
                       "': expected letters, digits, '_', '-' and '.', not starting with '.' (names become "
                       "file names)");
    if (!names.insert(c.name).second) throw SuiteError(where + ".name: '" + c.name + "' names two cases");
    where = suitePath + ": case '" + c.name + "'";
    for (const auto& [key, value] : entry.items())
      if (key != "name" && key != "input" && key != "options" && key != "golden" && key != "tolerances")
        throw SuiteError(where + ": unknown key '" + key +
                         "' (expected name, input, options, golden, tolerances)");
    const std::string input = requireString(entry, "input", where);
    c.input = isProceduralSpec(input) ? input : resolve(input);
    c.golden = resolve(requireString(entry, "golden", where));
    // Goldens are the renders' PNGs (--update copies one there): another name would hold PNG bytes.
    if (!hasExtension(c.golden, ".png"))
      throw SuiteError(where + ".golden: " + c.golden + ": expected a PNG file (a name ending in .png)");
    if (const auto options = entry.find("options"); options != entry.end()) {
      if (!options->is_array()) throw SuiteError(where + ".options: expected an array of strings");
      for (const json& option : *options) {
        if (!option.is_string())
          throw SuiteError(where + ".options: expected strings as on the command line, got " + option.dump());
        c.options.push_back(option.get<std::string>());
      }
    }
    c.tolerances = defaults;
    if (const auto tolerances = entry.find("tolerances"); tolerances != entry.end())
      c.tolerances = readTolerances(*tolerances, defaults, where + ": tolerances");
    suite.cases.push_back(std::move(c));
  }
  return suite;
}

RegressSuite loadRegressSuite(const std::string& suitePath) {
  std::string text;
  try {
    text = readTextInput(suitePath, suitePath + ": the suite file");
  } catch (const Error& e) {
    throw SuiteError(e.what());
  }
  return parseRegressSuite(text, suitePath);
}

}  // namespace ropecast::tools
