#include "tools/parse_error_text.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "tools/cli_values.h"

namespace ropecast::tools {
namespace {

// The subcommand the error arose in: the deepest one parsed ("ropecast bench modes").
const CLI::App* parsedCommand(const CLI::App& app, std::string& path) {
  path = "ropecast";
  const CLI::App* command = &app;
  for (;;) {
    const std::vector<const CLI::App*> parsed =
        command->get_subcommands([](const CLI::App* sub) { return sub->parsed(); });
    if (parsed.empty()) return command;
    command = parsed.front();
    path += " " + command->get_name();
  }
}

size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::vector<std::string> longOptionsOf(const CLI::App& command) {
  std::vector<std::string> names;
  for (const CLI::Option* option : command.get_options())
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
  return names;
}

// "The following argument(s) was/were not expected: A B" (CLI11 lists them last first).
std::string extrasText(const std::string& message, const CLI::App& command) {
  const size_t colon = message.find(": ");
  std::vector<std::string> extras;
  std::istringstream words(message.substr(colon + 2));
  for (std::string word; words >> word;) extras.insert(extras.begin(), word);
  std::string text;
  bool afterUnknownOption = false;
  for (const std::string& extra : extras) {
    const bool option = extra.size() > 1 && extra[0] == '-';
    if (!option && afterUnknownOption) {  // its value, most likely: no error of its own
      afterUnknownOption = false;
      continue;
    }
    text += text.empty() ? "" : "; ";
    if (option) {
      text += "unknown option " + extra.substr(0, extra.find('='));
      const std::vector<std::string> meant = likelyMeant(extra, longOptionsOf(command));
      if (!meant.empty()) text += " (did you mean " + alternatives(meant) + "?)";
    } else {
      text += "unexpected argument '" + extra + "'";
    }
    afterUnknownOption = option && extra.find('=') == std::string::npos;
  }
  return text;
}

// ArgumentMismatch's three forms, with what the option takes.
std::string mismatchText(const std::string& message, const CLI::App& command) {
  static const std::regex atLeast(R"(^(\S+): At least (\d+) required but received (\d+)$)");
  static const std::regex atMost(R"(^(\S+): At Most (\d+) required but received (\d+)$)");
  static const std::regex missing(R"(^(\S+): (\d+) required (\S+) missing$)");
  std::smatch m;
  const auto takes = [&command](const std::string& name, const std::string& count) {
    const CLI::Option* option = command.get_option_no_throw(name);
    const bool exact = option && option->get_items_expected_min() == option->get_items_expected_max();
    std::string text = (exact ? "" : "at least ") + count + (count == "1" ? " value" : " values");
    if (option && count != "1" && option->get_delimiter() != '\0')
      text += std::string(" separated by '") + option->get_delimiter() + "'";
    return text;
  };
  if (std::regex_match(message, m, atLeast))
    return m[1].str() + ": expected " + takes(m[1], m[2]) + ", got " + m[3].str();
  if (std::regex_match(message, m, atMost))
    return m[1].str() + ": expected " + (m[2] == "1" ? "1 value" : m[2].str() + " values") + ", got " +
           m[3].str();
  if (std::regex_match(message, m, missing))
    return m[1].str() + ": expected " + (m[2] == "1" ? "a value" : m[2].str() + " values") + " (" +
           m[3].str() + ") after it";
  return message;
}

// "Could not convert: --level = abc", for an option of a number type without a check of its own.
std::string conversionText(const std::string& message, const CLI::App& command) {
  static const std::regex couldNot(R"(^Could not convert: (\S+) = (.*)$)");
  std::smatch m;
  if (!std::regex_match(message, m, couldNot)) return message;
  const CLI::Option* option = command.get_option_no_throw(m[1]);
  const std::string type = option ? option->get_type_name() : "";
  const std::string expected = type.starts_with("UINT")    ? "an integer >= 0"
                               : type.starts_with("INT")   ? "an integer"
                               : type.starts_with("FLOAT") ? "a number"
                                                           : "a value of type " + type;
  return m[1].str() + ": expected " + expected + ", got '" + m[2].str() + "'";
}

// "input is required" / "--output is required", with what the option is.
std::string requiredText(const std::string& message, const CLI::App& command) {
  static const std::regex isRequired(R"(^(\S+) is required$)");
  std::smatch m;
  if (!std::regex_match(message, m, isRequired)) return message;
  const CLI::Option* option = command.get_option_no_throw(m[1]);
  if (!option || option->get_description().empty()) return message;
  return (option->nonpositional() ? m[1].str() + " is required: " : "missing " + m[1].str() + ": ") +
         option->get_description();
}

}  // namespace

std::vector<std::string> likelyMeant(const std::string& given, const std::vector<std::string>& options) {
  const std::string typed = given.substr(0, given.find('='));
  const size_t start = typed.find_first_not_of('-');
  if (start == std::string::npos) return {};  // "---": no name to compare
  const std::string bare = typed.substr(start);
  // One slip in a short name, two in a longer one ("--voxel-per-pixel" for "--voxels-per-pixel").
  const size_t tolerance = bare.size() <= 4 ? 1 : 2;
  std::vector<std::pair<size_t, std::string>> scored;
  for (const std::string& option : options) {
    const std::string name = option.substr(2);
    const size_t distance = editDistance(bare, name);
    if (distance <= tolerance || (bare.size() >= 3 && name.starts_with(bare)))
      scored.emplace_back(distance, option);
  }
  std::stable_sort(scored.begin(), scored.end(), [](auto& a, auto& b) { return a.first < b.first; });
  std::vector<std::string> meant;
  for (const auto& [distance, option] : scored)
    if (meant.size() < 3 && std::find(meant.begin(), meant.end(), option) == meant.end())
      meant.push_back(option);
  return meant;
}

std::string parseErrorText(const CLI::App& app, const CLI::ParseError& error) {
  std::string path;
  const CLI::App& command = *parsedCommand(app, path);
  const std::string message = error.what();
  // (An ExtrasError is named after the command it arose in, not its class.)
  if (dynamic_cast<const CLI::ExtrasError*>(&error)) return extrasText(message, command);
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&error)) return mismatchText(message, command);
  if (dynamic_cast<const CLI::ConversionError*>(&error)) return conversionText(message, command);
  if (dynamic_cast<const CLI::RequiredError*>(&error) && message != "A subcommand is required")
    return requiredText(message, command);
  if (message == "A subcommand is required") {
    std::vector<std::string> names;
    for (const CLI::App* sub : command.get_subcommands([](const CLI::App*) { return true; }))
      names.push_back(sub->get_name());
    return "a command is required: " + alternatives(names);
  }
  return message;
}

std::string parsedCommandPath(const CLI::App& app) {
  std::string path;
  parsedCommand(app, path);
  return path;
}

}  // namespace ropecast::tools
