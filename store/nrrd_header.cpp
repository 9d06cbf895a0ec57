#include "store/nrrd_header.h"

#include <cctype>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "core/error.h"
#include "core/header_text.h"
#include "core/number_text.h"
#include "store/volume_source.h"

namespace ropecast {
namespace {

std::optional<int64_t> parseInteger(std::string_view s) {
  return parseWholeNumber<int64_t>(s);
}

// Finite numbers and NaN (NRRD writes "nan" for unknown spacings); nullopt for anything else.
std::optional<double> parseNumber(std::string_view s) {
  const std::optional<double> v = parseWholeNumber<double>(s);
  if (v && std::isinf(*v)) return std::nullopt;
  return v;
}

// The types read, for messages (in any of the spec's spellings).
constexpr std::string_view kNrrdTypeList =
    "int8, uint8, int16, uint16, int32, uint32, float or double (or another of their NRRD spellings)";

std::optional<SampleType> parseNrrdType(std::string_view t) {
  // The spellings the NRRD format defines for each type ropecast reads.
  struct TypeNames {
    SampleType type;
    std::string_view names[6];
  };
  static const TypeNames kTypes[] = {
      {SampleType::Int8,
       {"signed char", "int8", "int8_t"}},  // not plain "char", whose signedness C leaves open
      {SampleType::UInt8, {"uchar", "unsigned char", "uint8", "uint8_t"}},
      {SampleType::Int16, {"short", "short int", "signed short", "signed short int", "int16", "int16_t"}},
      {SampleType::UInt16, {"ushort", "unsigned short", "unsigned short int", "uint16", "uint16_t"}},
      {SampleType::Int32, {"int", "signed int", "int32", "int32_t"}},
      {SampleType::UInt32, {"uint", "unsigned int", "uint32", "uint32_t"}},
      {SampleType::Float32, {"float"}},
      {SampleType::Float64, {"double"}},
  };
  for (const TypeNames& entry : kTypes)
    for (std::string_view name : entry.names)
      if (!name.empty() && name == t) return entry.type;
  return std::nullopt;
}

bool isKnownUnsupportedNrrdType(std::string_view t) {
  static const std::string_view kOthers[] = {
      "longlong", "long long", "long long int", "signed long long",   "signed long long int",
      "int64",    "int64_t",   "ulonglong",     "unsigned long long", "unsigned long long int",
      "uint64",   "uint64_t",  "block"};
  for (std::string_view o : kOthers)
    if (o == t) return true;
  return false;
}

class HeaderParser {
 public:
  HeaderParser(std::string_view text, const std::string& fileName) : text_(text), fileName_(fileName) {}

  NrrdHeader parse() {
    parseMagic();
    while (pos_ < text_.size()) {
      ++lineNumber_;
      const std::string_view line = nextLine();
      if (line.empty()) {
        header_.endsWithBlankLine = true;
        break;
      }
      parseLine(line);
    }
    header_.headerBytes = pos_;
    return finish();
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("NRRD header of " + fileName_ + ": " + what);
  }
  [[noreturn]] void failField(std::string_view field, const std::string& what) const {
    fail("field '" + std::string(field) + "' (line " + std::to_string(lineNumber_) + "): " + what);
  }

  std::string_view nextLine() { return takeLine(text_, pos_); }

  void parseMagic() {
    lineNumber_ = 1;
    const bool hasNewline = text_.find('\n') != std::string_view::npos;
    const std::string_view magic = nextLine();
    if (!hasNewline || magic.size() != 8 || magic.substr(0, 7) != "NRRD000" || magic[7] < '1' ||
        magic[7] > '9')
      fail("expected the magic line NRRD0001..NRRD0009 followed by a newline, got " + quotedExcerpt(magic));
  }

  void parseLine(std::string_view line) {
    if (line.front() == '#') return;  // comment
    const size_t keyValue = line.find(":=");
    const size_t field = line.find(": ");
    if (keyValue != std::string_view::npos && (field == std::string_view::npos || keyValue < field)) return;
    if (field == std::string_view::npos)
      fail("line " + std::to_string(lineNumber_) + ": expected 'field: value' or 'key:=value', got " +
           quotedExcerpt(line));
    const std::string_view name = line.substr(0, field);
    const std::string_view value = trimBlanks(line.substr(field + 2));
    if (!seen_.insert(std::string(name)).second) failField(name, "given more than once");
    if (name == "dimension") {
      const auto d = parseInteger(value);
      if (!d) failField(name, "expected an integer, got " + quotedExcerpt(value));
      if (*d != 3 && *d != 4)
        failField(name, "expected 3 (a volume) or 4 (volumes along a time, list or vector axis), got " +
                            std::to_string(*d));
      rank_ = int(*d);
      dimension_ = true;
    } else if (name == "type") {
      const auto t = parseNrrdType(value);
      if (!t) {
        if (isKnownUnsupportedNrrdType(value))
          failField(name,
                    "unsupported type " + quotedExcerpt(value) + "; expected " + std::string(kNrrdTypeList));
        failField(name, "unknown type " + quotedExcerpt(value) + "; expected " + std::string(kNrrdTypeList));
      }
      header_.type = *t;
      type_ = true;
    } else if (rank_ == 4 && (name == "sizes" || name == "spacings" || name == "space directions")) {
      perAxis_[std::string(name)] = {std::string(value),
                                     lineNumber_};  // the non-spatial axis is known at the end
    } else if (name == "kinds") {
      kinds_ = axisWords(value);
      kindsLine_ = lineNumber_;
    } else if (name == "sizes") {
      parseSizes(name, value);
    } else if (name == "encoding") {
      parseEncoding(name, value);
    } else if (name == "endian") {
      if (value == "little")
        header_.bigEndian = false;
      else if (value == "big")
        header_.bigEndian = true;
      else
        failField(name, "expected little or big, got " + quotedExcerpt(value));
      endian_ = true;
    } else if (name == "spacings") {
      parseSpacings(name, value);
    } else if (name == "space directions") {
      parseSpaceDirections(name, value);
    } else if (name == "space") {
      space_ = std::string(value);
    } else if (name == "space origin") {
      parseSpaceOrigin(value);
    } else if (name == "byte skip") {
      const auto skip = parseInteger(value);
      if (!skip || *skip < -1 || *skip > kMaxSkip)
        failField(name, "expected an integer in [-1, " + std::to_string(kMaxSkip) + "], got " +
                            quotedExcerpt(value));
      header_.byteSkip = *skip;
    } else if (name == "line skip") {
      const auto skip = parseInteger(value);
      if (!skip || *skip < 0 || *skip > kMaxSkip)
        failField(name, "expected an integer in [0, " + std::to_string(kMaxSkip) + "], got " +
                            quotedExcerpt(value));
      header_.lineSkip = *skip;
    } else if (name == "data file" || name == "datafile") {
      parseDataFile(name, value);
    }
    // Anything else (kinds, centerings, content, ...) does not change how samples are read or placed.
  }

  void parseSizes(std::string_view name, std::string_view value) {
    const SizesText parsed = parseSizesText(value);
    if (!parsed.problem.empty()) failField(name, parsed.problem);
    header_.sizes = parsed.sizes;
    sizes_ = true;
  }

  void parseEncoding(std::string_view name, std::string_view value) {
    if (value == "raw") {
      header_.encoding = NrrdEncoding::Raw;
    } else if (value == "gzip" || value == "gz") {
      header_.encoding = NrrdEncoding::Gzip;
    } else if (value == "ascii" || value == "text" || value == "txt" || value == "hex" || value == "bzip2" ||
               value == "bz2" || value == "zrl") {
      failField(name, "unsupported encoding " + quotedExcerpt(value) + "; expected raw or gzip");
    } else {
      failField(name, "unknown encoding " + quotedExcerpt(value) + "; expected raw or gzip");
    }
    encoding_ = true;
  }

  void parseSpacings(std::string_view name, std::string_view value) {
    const auto words = splitWords(value);
    if (words.size() != 3) failField(name, "expected 3 numbers, got " + quotedExcerpt(value));
    for (int axis = 0; axis < 3; ++axis) {
      const auto s = parseNumber(words[axis]);
      if (!s) failField(name, "expected 3 numbers, got " + quotedExcerpt(value));
      if (*s == 0.0) failField(name, "spacing of axis " + std::to_string(axis) + " is zero");
      spacings_[axis] = std::isnan(*s) ? 1.0 : std::abs(*s);
    }
    hasSpacings_ = true;
  }

  void parseSpaceDirections(std::string_view name, std::string_view value) {
    glm::dvec3 lengths(1.0);
    int axis = 0;
    size_t i = 0;
    std::optional<size_t> components;
    while (true) {
      while (i < value.size() && (value[i] == ' ' || value[i] == '\t')) ++i;
      if (i == value.size()) break;
      if (axis == 3) failField(name, "expected 3 vectors or 'none', got " + quotedExcerpt(value));
      if (value.substr(i, 4) == "none") {
        i += 4;
        ++axis;
        vectorsUsable_ = false;
        continue;
      }
      if (value[i] != '(') failField(name, "expected '(x,y,z)' or 'none', got " + quotedExcerpt(value));
      const size_t close = value.find(')', i);
      if (close == std::string_view::npos) failField(name, "missing ')' in " + quotedExcerpt(value));
      const std::string_view inner = value.substr(i + 1, close - i - 1);
      double squared = 0.0;
      size_t count = 0;
      for (size_t start = 0;;) {
        const size_t comma = inner.find(',', start);
        const auto c = parseNumber(
            inner.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start));
        if (!c || std::isnan(*c)) failField(name, "expected numbers in " + quotedExcerpt(value));
        squared += *c * *c;
        if (count < 3) vectors_[axis][int(count)] = *c;
        ++count;
        if (comma == std::string_view::npos) break;
        start = comma + 1;
      }
      if (components && *components != count)
        failField(name, "vectors of different lengths in " + quotedExcerpt(value));
      components = count;
      const double length = std::sqrt(squared);
      if (!(length > 0.0) || std::isinf(length))
        failField(name, "direction of axis " + std::to_string(axis) + " has zero or infinite length");
      if (count != 3) vectorsUsable_ = false;
      lengths[axis++] = length;
      i = close + 1;
    }
    if (axis != 3) failField(name, "expected 3 vectors or 'none', got " + quotedExcerpt(value));
    directions_ = lengths;
    hasDirections_ = true;
  }

  // "(x,y,z)"; Teem writes "(nan,nan,nan)" for an unknown origin.
  void parseSpaceOrigin(std::string_view value) {
    while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.remove_suffix(1);
    glm::dvec3 origin(0.0);
    int count = 0;
    bool finite = value.size() >= 2 && value.front() == '(' && value.back() == ')';
    const std::string_view inner = finite ? value.substr(1, value.size() - 2) : std::string_view();
    for (size_t start = 0; finite;) {
      const size_t comma = inner.find(',', start);
      const auto number =
          parseNumber(inner.substr(start, comma == std::string_view::npos ? comma : comma - start));
      finite = number && std::isfinite(*number) && count < 3;
      if (finite) origin[count++] = *number;
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    finite = finite && count == 3;
    rawOrigin_ = finite ? std::optional(origin) : std::nullopt;
    originNotRead_ = !finite && value.find("nan") == std::string_view::npos;
  }

  void parseDataFile(std::string_view name, std::string_view value) {
    if (value.empty()) failField(name, "expected a file name");
    const auto words = splitWords(value);
    const bool isList = value == "LIST" || (value.size() > 5 && value.substr(0, 5) == "LIST ");
    bool isFormat = words.size() >= 4;  // "<format> <min> <max> <step> [<subdim>]"
    for (size_t w = 1; isFormat && w < words.size(); ++w) isFormat = parseInteger(words[w]).has_value();
    if (isList || isFormat)
      failField(name, "multiple data files are not supported, got " + quotedExcerpt(value));
    header_.dataFile = std::string(value);
  }

  // A per-axis field's entries: words, a vector "(x, y, z)" one entry whatever spaces it holds.
  static std::vector<std::string> axisWords(std::string_view value) {
    std::vector<std::string> words;
    int depth = 0;
    bool inWord = false;
    for (const char c : value) {
      const bool blank = (c == ' ' || c == '\t') && depth == 0;
      if (blank) {
        inWord = false;
        continue;
      }
      if (!inWord) words.emplace_back();
      inWord = true;
      words.back() += c;
      depth += c == '(' ? 1 : c == ')' ? -1 : 0;
    }
    return words;
  }

  // Dimension 4: finds the axis that is not spatial, reads the per-axis fields without it, and says where the
  // volumes along it lie.
  void resolveFourthAxis() {
    if (!perAxis_.contains("sizes")) return;  // missing, said below
    int extra = -1;
    if (!kinds_.empty()) {
      lineNumber_ = kindsLine_;
      if (kinds_.size() != 4)
        failField("kinds", "expected 4 kinds (dimension 4), got " + std::to_string(kinds_.size()));
      for (int a = 0; a < 4; ++a)
        if (kinds_[size_t(a)] != "domain" && kinds_[size_t(a)] != "space") {
          if (extra >= 0)
            failField("kinds", "two axes (" + std::to_string(extra) + " and " + std::to_string(a) +
                                   ") are not domain or space; one of four may be another kind");
          extra = a;
        }
      if (extra < 0)
        failField(
            "kinds",
            "every axis is domain or space; one of four must be another kind (time, list, vector, ...)");
    } else if (const auto it = perAxis_.find("space directions"); it != perAxis_.end()) {
      lineNumber_ = it->second.second;
      const std::vector<std::string> words = axisWords(it->second.first);
      if (words.size() != 4)
        failField("space directions",
                  "expected 4 entries (dimension 4), got " + quotedExcerpt(it->second.first));
      for (int a = 0; a < int(words.size()); ++a)
        if (words[size_t(a)] == "none") {
          if (extra >= 0) failField("space directions", "two axes are 'none'; one of four may be");
          extra = a;
        }
    }
    if (extra < 0) fail("dimension 4, but neither kinds nor space directions say which axis is not spatial");
    if (extra == 1 || extra == 2)
      fail("axis " + std::to_string(extra) +
           " is not spatial and lies between spatial ones; the first (interleaved) or the last is read");
    header_.volumesInterleaved = extra == 0;
    header_.volumesAreTimePoints = !kinds_.empty() && kinds_[size_t(extra)] == "time";
    for (const auto& [name, written] : perAxis_) {
      const auto& [value, line] = written;
      lineNumber_ = line;
      std::vector<std::string> words = axisWords(value);
      if (words.size() != 4) failField(name, "expected 4 entries (dimension 4), got " + quotedExcerpt(value));
      if (name == "sizes") {
        const auto volumes = parseWholeNumber<uint32_t>(words[size_t(extra)]);
        if (!volumes || *volumes == 0)
          failField(name, "expected positive sizes, got " + quotedExcerpt(value));
        header_.volumes = *volumes;
      }
      words.erase(words.begin() + extra);
      const std::string spatial = words[0] + " " + words[1] + " " + words[2];
      if (name == "sizes")
        parseSizes(name, spatial);
      else if (name == "spacings")
        parseSpacings(name, spatial);
      else
        parseSpaceDirections(name, spatial);
    }
    lineNumber_ = perAxis_.at("sizes").second;
    if (header_.dataBytes() > (uint64_t(1) << 62) / header_.volumes)
      failField("sizes", "the " + std::to_string(header_.volumes) + " volumes are more than 2^62 bytes");
  }

  NrrdHeader finish() {
    if (!dimension_) fail("missing field 'dimension'");
    if (!type_) fail("missing field 'type'");
    if (rank_ == 4) resolveFourthAxis();
    if (!type_) fail("missing field 'type'");
    if (!sizes_) fail("missing field 'sizes'");
    if (!encoding_) fail("missing field 'encoding'");
    if (!endian_ && bytesPerSample(header_.type) > 1)
      fail("missing field 'endian' (required for " + std::string(sampleTypeName(header_.type)) + " data)");
    if (header_.byteSkip == -1 && header_.encoding != NrrdEncoding::Raw)
      fail("field 'byte skip': -1 is only allowed with raw encoding");
    if (hasDirections_) {
      header_.spacing = directions_;
      const std::optional<AxisDirections> axes =
          vectorsUsable_ ? axisDirectionsOf(vectors_[0], vectors_[1], vectors_[2]) : std::nullopt;
      if (axes) {
        header_.axes = inLps(*axes);
      } else {
        header_.directionsNotApplied = true;
        if (vectorsUsable_) {
          const glm::dvec3 signs = lpsSigns();
          header_.shearedDirections = {signs * vectors_[0], signs * vectors_[1], signs * vectors_[2]};
        }
      }
    } else if (hasSpacings_) {
      header_.spacing = spacings_;
    }
    if (rawOrigin_) header_.origin = lpsSigns() * *rawOrigin_;
    header_.anatomicalSpace = isAnatomicalSpace();
    header_.originNotRead = originNotRead_;
    return header_;
  }

  // The space directions in LPS, from the anatomical frame the "space" field names (NRRD's long and short
  // names); a space that is not anatomical (scanner-xyz, 3D-right-handed, none given) as it is.
  AxisDirections inLps(const AxisDirections& axes) const {
    AxisDirections lps = axes;
    for (int a = 0; a < 3; ++a) lps[a] *= lpsSigns();
    return lps;
  }
  // The "space" field in lower case, as NRRD's names compare.
  std::string lowerSpace() const {
    std::string space;
    for (const char c : space_) space += char(std::tolower(static_cast<unsigned char>(c)));
    return space;
  }
  // Whether the "space" field names a patient's frame: NRRD's long names (right-anterior-superior, ...) and
  // short ones (RAS, LAS, LPS), with or without "-time".
  bool isAnatomicalSpace() const {
    const std::string space = lowerSpace();
    return space.starts_with("right-") || space.starts_with("left-") || space.starts_with("ras") ||
           space.starts_with("las") || space.starts_with("lps");
  }
  // What turns a vector of the "space" field's frame into LPS: -1 on the axes that point the other way.
  glm::dvec3 lpsSigns() const {
    const std::string space = lowerSpace();
    const bool right = space.starts_with("right-") || space.starts_with("ra");
    const bool anterior = space.starts_with("right-anterior") || space.starts_with("left-anterior") ||
                          space.starts_with("ra") || space.starts_with("la");
    return {right ? -1.0 : 1.0, anterior ? -1.0 : 1.0, 1.0};
  }

  static constexpr int64_t kMaxSkip = int64_t(1) << 40;

  std::string_view text_;
  const std::string& fileName_;
  size_t pos_ = 0;
  size_t lineNumber_ = 0;
  NrrdHeader header_;
  std::set<std::string> seen_;
  bool dimension_ = false, type_ = false, sizes_ = false, encoding_ = false, endian_ = false;
  int rank_ = 3;
  // Dimension 4: sizes, spacings and space directions as written, with their lines.
  std::map<std::string, std::pair<std::string, size_t>> perAxis_;
  std::vector<std::string> kinds_;
  size_t kindsLine_ = 0;
  bool hasSpacings_ = false, hasDirections_ = false;
  glm::dvec3 spacings_{1.0};
  glm::dvec3 directions_{1.0};
  glm::dvec3 vectors_[3] = {glm::dvec3(0.0), glm::dvec3(0.0), glm::dvec3(0.0)};  // the space directions
  bool vectorsUsable_ = true;                                                    // three 3-vectors, no "none"
  std::optional<glm::dvec3> rawOrigin_;  // the space origin in the "space" field's frame
  bool originNotRead_ = false;
  std::string space_;
};

}  // namespace

NrrdHeader parseNrrdHeader(std::string_view text, const std::string& fileName) {
  return HeaderParser(text, fileName).parse();
}

}  // namespace ropecast
