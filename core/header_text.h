// Text fields of file headers (NRRD, MetaImage): blanks trimmed, words split, a bad value quoted in a
// message, and names listed in one. Pure functions; any thread.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace ropecast {

inline bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

// `s` with ASCII letters in lower case, for keys and values that are read in any case.
inline std::string lowerAscii(std::string_view s) {
  std::string out(s);
  for (char& c : out)
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
  return out;
}

// `s` without the blanks (spaces, tabs, line ends) at either end.
inline std::string_view trimBlanks(std::string_view s) {
  while (!s.empty() && isBlank(s.front())) s.remove_prefix(1);
  while (!s.empty() && isBlank(s.back())) s.remove_suffix(1);
  return s;
}

// The line of `text` that starts at `pos`, without its line end ("\n" or "\r\n"); `pos` moves past the line
// end, or to the text's end where no line end follows.
inline std::string_view takeLine(std::string_view text, size_t& pos) {
  const size_t end = text.find('\n', pos);
  std::string_view line =
      text.substr(pos, end == std::string_view::npos ? std::string_view::npos : end - pos);
  pos = end == std::string_view::npos ? text.size() : end + 1;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

// The words of `s`, separated by spaces and tabs.
inline std::vector<std::string_view> splitWords(std::string_view s) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
    const size_t start = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t') ++i;
    if (i > start) words.push_back(s.substr(start, i - start));
  }
  return words;
}

// `s` in quotes for a message: its first 60 characters, control and non-ASCII bytes shown as '?'.
inline std::string quotedExcerpt(std::string_view s) {
  constexpr size_t kQuoteChars = 60;
  std::string out(s.substr(0, kQuoteChars));
  for (char& c : out)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  return "'" + out + (s.size() > kQuoteChars ? "...'" : "'");
}

// The first `shown` of `names`, comma-separated, and how many more there are: a list in a message.
inline std::string listedNames(const std::vector<std::string>& names, size_t shown = 8) {
  std::string text;
  for (size_t i = 0; i < names.size() && i < shown; ++i) text += (i ? ", " : "") + names[i];
  if (names.size() > shown) text += " and " + std::to_string(names.size() - shown) + " more";
  return text;
}

}  // namespace ropecast
