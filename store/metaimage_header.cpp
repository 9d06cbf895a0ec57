#include "store/metaimage_header.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <set>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "core/number_text.h"
#include "store/volume_source.h"

namespace ropecast {
namespace {

// A patient orientation code as MetaImage's AnatomicalOrientation writes it: three letters, one of each pair
// R/L, A/P, S/I, in any order and case ("RAI", "lps").
bool isPatientOrientationCode(std::string_view code) {
  if (code.size() != 3) return false;
  const std::string_view pairs[] = {"RL", "AP", "SI"};
  bool seen[3] = {false, false, false};
  for (const char c : code) {
    const char upper = char(std::toupper(static_cast<unsigned char>(c)));
    bool found = false;
    for (int p = 0; p < 3; ++p)
      if (pairs[p].find(upper) != std::string_view::npos && !seen[p]) found = seen[p] = true;
    if (!found) return false;
  }
  return true;
}

// The element types read, for messages.
constexpr std::string_view kMetaTypeList =
    "MET_CHAR, MET_UCHAR, MET_SHORT, MET_USHORT, MET_INT, MET_UINT, MET_LONG, MET_ULONG, MET_FLOAT or "
    "MET_DOUBLE";

std::optional<SampleType> parseMetaType(std::string_view t) {
  struct TypeName {
    std::string_view name;
    SampleType type;
  };
  // MetaIO's MET_LONG and MET_ULONG are 4 bytes whatever the platform's long (its MET_ValueTypeSize).
  static constexpr TypeName kTypes[] = {
      {"MET_CHAR", SampleType::Int8},     {"MET_UCHAR", SampleType::UInt8},
      {"MET_SHORT", SampleType::Int16},   {"MET_USHORT", SampleType::UInt16},
      {"MET_INT", SampleType::Int32},     {"MET_UINT", SampleType::UInt32},
      {"MET_LONG", SampleType::Int32},    {"MET_ULONG", SampleType::UInt32},
      {"MET_FLOAT", SampleType::Float32}, {"MET_DOUBLE", SampleType::Float64}};
  for (const TypeName& entry : kTypes)
    if (entry.name == t) return entry.type;
  return std::nullopt;
}

class MetaImageHeaderParser {
 public:
  MetaImageHeaderParser(std::string_view text, const std::string& fileName)
      : text_(text), fileName_(fileName) {}

  MetaImageHeader parse() {
    while (pos_ < text_.size() && !dataFileSeen_) {
      ++lineNumber_;
      const std::string_view line = nextLine();
      if (!trimBlanks(line).empty()) parseLine(line);
    }
    if (listed_)  // LIST: a file name a line, to the end of the header's file
      while (pos_ < text_.size()) {
        ++lineNumber_;
        const std::string_view name = trimBlanks(nextLine());
        if (!name.empty()) header_.sliceFiles.emplace_back(name);
      }
    header_.headerBytes = pos_;
    return finish();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("MetaImage header of " + fileName_ + ": " + what);
  }
  [[noreturn]] void failKey(std::string_view key, const std::string& what) const {
    fail("key '" + std::string(key) + "' (line " + std::to_string(lineNumber_) + "): " + what);
  }

  std::string_view nextLine() { return takeLine(text_, pos_); }

  std::vector<double> numbers(std::string_view key, std::string_view value, size_t count) const {
    const auto words = splitWords(value);
    if (words.size() != count)
      failKey(key, "expected " + std::to_string(count) + " numbers, got " + quotedExcerpt(value));
    std::vector<double> out;
    for (std::string_view word : words) {
      const auto n = parseWholeNumber<double>(word);
      if (!n || !std::isfinite(*n))
        failKey(key, "expected " + std::to_string(count) + " numbers, got " + quotedExcerpt(value));
      out.push_back(*n);
    }
    return out;
  }

  int64_t integer(std::string_view key, std::string_view value, int64_t lo, int64_t hi) const {
    const auto n = parseWholeNumber<int64_t>(value);
    if (!n || *n < lo || *n > hi)
      failKey(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                       quotedExcerpt(value));
    return *n;
  }

  bool boolean(std::string_view key, std::string_view value) const {
    const std::string v = lowerAscii(value);
    if (v == "true" || v == "t" || v == "1") return true;
    if (v == "false" || v == "f" || v == "0") return false;
    failKey(key, "expected True or False, got " + quotedExcerpt(value));
  }

  glm::dvec3 spacing(std::string_view key, std::string_view value) const {
    const std::vector<double> s = numbers(key, value, 3);
    for (int axis = 0; axis < 3; ++axis)
      if (s[axis] == 0.0) failKey(key, "spacing of axis " + std::to_string(axis) + " is zero");
    return glm::dvec3(std::abs(s[0]), std::abs(s[1]), std::abs(s[2]));
  }

  void parseLine(std::string_view line) {
    const size_t equals = line.find('=');
    if (equals == std::string_view::npos)
      fail("line " + std::to_string(lineNumber_) + ": expected 'Key = Value', got " + quotedExcerpt(line));
    const std::string_view key = trimBlanks(line.substr(0, equals));
    const std::string_view value = trimBlanks(line.substr(equals + 1));
    const std::string name = lowerAscii(key);
    if (!seen_.insert(name).second) failKey(key, "given more than once");
    if (name == "objecttype") {
      if (lowerAscii(value) != "image") failKey(key, "expected Image, got " + quotedExcerpt(value));
    } else if (name == "ndims") {
      const int64_t n = integer(key, value, 1, 64);
      if (n != 3) failKey(key, "only 3-dimensional volumes are supported, got " + std::to_string(n));
    } else if (name == "dimsize") {
      parseSizes(key, value);
    } else if (name == "elementtype") {
      const auto t = parseMetaType(value);
      if (!t)
        failKey(key, "unsupported element type " + quotedExcerpt(value) + "; expected " +
                         std::string(kMetaTypeList));
      header_.type = *t;
      type_ = true;
    } else if (name == "elementspacing") {
      header_.spacing = spacing(key, value);
      elementSpacing_ = true;
    } else if (name == "elementsize") {
      if (!elementSpacing_) header_.spacing = spacing(key, value);
    } else if (name == "binarydata") {
      if (!boolean(key, value))
        failKey(key, "ASCII data (BinaryData = False) is not supported; expected binary data");
    } else if (name == "binarydatabyteordermsb" || name == "elementbyteordermsb") {
      const bool big = boolean(key, value);
      if (byteOrder_ && *byteOrder_ != big)
        failKey(key, "contradicts the byte order given by the other ...ByteOrderMSB key");
      byteOrder_ = big;
      header_.bigEndian = big;
    } else if (name == "compresseddata") {
      header_.compressed = boolean(key, value);
    } else if (name == "headersize") {
      header_.headerSize = integer(key, value, -1, kMaxSkip);
    } else if (name == "elementnumberofchannels") {
      header_.channels = uint32_t(integer(key, value, 1, 1 << 16));
    } else if (name == "transformmatrix" || name == "rotation" || name == "orientation") {
      const std::vector<double> m = numbers(key, value, 9);
      const std::optional<AxisDirections> axes =
          axisDirectionsOf({m[0], m[1], m[2]}, {m[3], m[4], m[5]}, {m[6], m[7], m[8]});
      header_.axes = axes.value_or(AxisDirections(1.0));
      header_.matrixNotApplied = !axes;
      header_.shearedMatrix.reset();
      if (!axes && std::all_of(m.begin(), m.end(), [](double v) { return std::isfinite(v); }))
        header_.shearedMatrix = {glm::dvec3(m[0], m[1], m[2]), glm::dvec3(m[3], m[4], m[5]),
                                 glm::dvec3(m[6], m[7], m[8])};
    } else if (name == "offset" || name == "origin" || name == "position") {
      const std::vector<double> o = numbers(key, value, 3);
      header_.origin = glm::dvec3(o[0], o[1], o[2]);
    } else if (name == "elementdatafile") {
      parseDataFile(key, value);
    } else if (name == "anatomicalorientation") {
      header_.anatomicalOrientation = isPatientOrientationCode(value);
    }
    // Anything else (CenterOfRotation, ElementMin, Comment, ...) does not change how samples are read or
    // placed.
  }

  void parseSizes(std::string_view key, std::string_view value) {
    const SizesText parsed = parseSizesText(value);
    if (!parsed.problem.empty()) failKey(key, parsed.problem);
    header_.sizes = parsed.sizes;
    sizes_ = true;
  }

  void parseDataFile(std::string_view key, std::string_view value) {
    if (value.empty()) failKey(key, "expected LOCAL or a file name");
    const auto words = splitWords(value);
    const std::string first = lowerAscii(words.front());
    bool isPattern = words.size() == 4;  // "<printf pattern> <min> <max> <step>"
    for (size_t w = 1; isPattern && w < words.size(); ++w)
      isPattern = parseWholeNumber<int64_t>(words[w]).has_value();
    dataFileSeen_ = true;
    if (first == "list") {
      if (words.size() > 2 || (words.size() == 2 && lowerAscii(words[1]) != "2d"))
        failKey(key, "expected LIST or LIST 2D (a file per slice), got " + quotedExcerpt(value));
      listed_ = true;
    } else if (isPattern) {
      expandPattern(key, words);
    } else if (lowerAscii(value) != "local") {
      header_.dataFile = std::string(value);
    }
  }

  // "slice%03d.raw 1 100 1": the names printf would make of the numbers from the first to the second by the
  // third, the pattern holding one %d (or %i) with an optional 0 and width, and %% for a percent sign.
  void expandPattern(std::string_view key, const std::vector<std::string_view>& words) {
    const std::string_view pattern = words[0];
    const int64_t from = *parseWholeNumber<int64_t>(words[1]), to = *parseWholeNumber<int64_t>(words[2]),
                  step = *parseWholeNumber<int64_t>(words[3]);
    std::string before, after;
    std::optional<std::pair<bool, int>> conversion;  // zero-padded, width
    for (size_t i = 0; i < pattern.size(); ++i) {
      std::string& text = conversion ? after : before;
      if (pattern[i] != '%') {
        text += pattern[i];
        continue;
      }
      if (i + 1 < pattern.size() && pattern[i + 1] == '%') {
        text += '%';
        ++i;
        continue;
      }
      size_t j = i + 1;
      const bool zero = j < pattern.size() && pattern[j] == '0';
      int width = 0;
      while (j < pattern.size() && std::isdigit(static_cast<unsigned char>(pattern[j])) && width < 100)
        width = width * 10 + (pattern[j++] - '0');
      if (conversion || j >= pattern.size() || (pattern[j] != 'd' && pattern[j] != 'i'))
        failKey(key, "the file name pattern " + quotedExcerpt(pattern) +
                         " must hold one %d (with an optional 0 and width, as slice%03d.raw)");
      conversion = std::pair(zero, width);
      i = j;
    }
    if (!conversion)
      failKey(key, "the file name pattern " + quotedExcerpt(pattern) + " holds no %d for the slice numbers");
    if (step == 0 || (step > 0) != (to >= from) || from < -(int64_t(1) << 40) || from > (int64_t(1) << 40) ||
        to < -(int64_t(1) << 40) || to > (int64_t(1) << 40))
      failKey(key, "expected numbers from " + std::string(words[1]) + " to " + std::string(words[2]) +
                       " by a step " + "that reaches it, got step " + std::string(words[3]));
    const uint64_t count = uint64_t((to - from) / step) + 1;
    if (count > kMaxDimsPerAxis)
      failKey(key, "the pattern gives " + std::to_string(count) + " files; a volume has at most " +
                       std::to_string(kMaxDimsPerAxis) + " slices");
    for (uint64_t k = 0; k < count; ++k) {
      const int64_t n = from + int64_t(k) * step;
      std::string digits = std::to_string(n < 0 ? -n : n);
      const size_t width = size_t(conversion->second) - (n < 0 ? 1 : 0);
      if (digits.size() < width) digits.insert(0, width - digits.size(), conversion->first ? '0' : ' ');
      header_.sliceFiles.push_back(before + (n < 0 ? "-" : "") + digits + after);
    }
  }

  MetaImageHeader finish() {
    if (!dataFileSeen_) fail("no ElementDataFile key, which ends a MetaImage header");
    if (!sizes_) fail("missing key 'DimSize'");
    if (!type_) fail("missing key 'ElementType'");
    // Sizes keep a channel's bytes within 2^62 (at 8 bytes a sample); so many channels could not.
    const uint64_t channelBytes =
        uint64_t(header_.sizes.x) * header_.sizes.y * header_.sizes.z * bytesPerSample(header_.type);
    if (channelBytes > (uint64_t(1) << 62) / header_.channels)
      fail("key 'ElementNumberOfChannels': " + std::to_string(header_.channels) +
           " channels of these sizes are more than 2^62 bytes");
    if (header_.headerSize == -1 && header_.compressed)
      fail("key 'HeaderSize': -1 (data at the end of the file) is only allowed for uncompressed data");
    if (listed_ || !header_.sliceFiles.empty()) {
      if (header_.sliceFiles.size() != header_.sizes.z)
        fail("key 'ElementDataFile': " + std::to_string(header_.sliceFiles.size()) + " data files for " +
             std::to_string(header_.sizes.z) + " slices (DimSize); expected a file per slice");
    }
    return header_;
  }

  static constexpr int64_t kMaxSkip = int64_t(1) << 40;

  std::string_view text_;
  const std::string& fileName_;
  size_t pos_ = 0;
  size_t lineNumber_ = 0;
  MetaImageHeader header_;
  std::set<std::string> seen_;
  std::optional<bool> byteOrder_;
  bool sizes_ = false, type_ = false, elementSpacing_ = false, dataFileSeen_ = false;
  bool listed_ = false;  // ElementDataFile = LIST: the file names follow
};

}  // namespace

MetaImageHeader parseMetaImageHeader(std::string_view text, const std::string& fileName) {
  return MetaImageHeaderParser(text, fileName).parse();
}

}  // namespace ropecast
