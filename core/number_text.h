// Numbers written as text in file headers (NRRD fields, DICOM values), where the whole field must be the
// number. Pure functions; any thread.
#pragma once

#include <charconv>
#include <optional>
#include <string_view>

#include "core/header_text.h"

namespace ropecast {

// `text` as a number of type T, with blanks (spaces, tabs, line ends) around it and a leading '+' allowed;
// nullopt when anything else is there or it does not fit T. For floating types "inf" and "nan" are numbers:
// callers that need finite values check them.
template <typename T>
std::optional<T> parseWholeNumber(std::string_view text) {
  text = trimBlanks(text);
  if (!text.empty() && text.front() == '+') {
    text.remove_prefix(1);
    if (!text.empty() && text.front() == '-') return std::nullopt;  // "+-1"
  }
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace ropecast
