#include "store/vtk_header.h"

#include <cmath>
#include <optional>
#include <vector>

#include "core/error.h"
#include "core/header_text.h"
#include "core/number_text.h"
#include "store/volume_source.h"

namespace ropecast {
namespace {

// The types read, for messages.
constexpr std::string_view kVtkTypeList =
    "char, unsigned_char, short, unsigned_short, int, unsigned_int, float or double";

std::optional<SampleType> parseVtkType(std::string_view name) {
  struct TypeName {
    std::string_view name;
    SampleType type;
  };
  static constexpr TypeName kTypes[] = {{"unsigned_char", SampleType::UInt8},
                                        {"char", SampleType::Int8},
                                        {"signed_char", SampleType::Int8},
                                        {"unsigned_short", SampleType::UInt16},
                                        {"short", SampleType::Int16},
                                        {"unsigned_int", SampleType::UInt32},
                                        {"int", SampleType::Int32},
                                        {"float", SampleType::Float32},
                                        {"double", SampleType::Float64},
                                        {"vtktypeuint8", SampleType::UInt8},
                                        {"vtktypeint8", SampleType::Int8},
                                        {"vtktypeuint16", SampleType::UInt16},
                                        {"vtktypeint16", SampleType::Int16},
                                        {"vtktypeuint32", SampleType::UInt32},
                                        {"vtktypeint32", SampleType::Int32},
                                        {"vtktypefloat32", SampleType::Float32},
                                        {"vtktypefloat64", SampleType::Float64}};
  const std::string lower = lowerAscii(name);
  for (const TypeName& entry : kTypes)
    if (entry.name == lower) return entry.type;
  return std::nullopt;
}

class VtkHeaderParser {
 public:
  VtkHeaderParser(std::string_view text, const std::string& fileName) : text_(text), fileName_(fileName) {}

  VtkHeader parse() {
    const std::string_view magic = nextLine();
    if (lowerAscii(magic).rfind("# vtk datafile version", 0) != 0)
      fail("expected the line '# vtk DataFile Version x.x' first, got " + quotedExcerpt(magic));
    nextLine();  // the title
    const std::string format = lowerAscii(trimBlanks(nextLine()));
    if (format != "binary" && format != "ascii")
      fail("line 3: expected ASCII or BINARY, got " + quotedExcerpt(format));
    header_.ascii = format == "ascii";
    while (!dataStarts_) {
      if (pos_ >= text_.size())
        fail("ends before the samples (expected POINT_DATA followed by SCALARS or FIELD)");
      const std::string_view line = nextLine();
      const auto words = splitWords(trimBlanks(line));
      if (!words.empty()) parseLine(words, line);
    }
    header_.headerBytes = pos_;
    return header_;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw Error("legacy VTK header of " + fileName_ + ": " + what);
  }
  [[noreturn]] void failLine(const std::string& what) const {
    fail("line " + std::to_string(lineNumber_) + ": " + what);
  }

  std::string_view nextLine() {
    ++lineNumber_;
    return takeLine(text_, pos_);
  }

  glm::dvec3 spacing(std::string_view line, const std::vector<std::string_view>& words) const {
    glm::dvec3 s;
    for (int axis = 0; axis < 3; ++axis) {
      const auto n = words.size() == 4 ? parseWholeNumber<double>(words[size_t(axis) + 1]) : std::nullopt;
      if (!n || !std::isfinite(*n) || *n == 0.0)
        failLine("expected 3 non-zero numbers after " + std::string(words[0]) + ", got " +
                 quotedExcerpt(line));
      s[axis] = std::abs(*n);
    }
    return s;
  }

  void parseLine(const std::vector<std::string_view>& words, std::string_view line) {
    const std::string keyword = lowerAscii(words[0]);
    const auto rest = [&] {
      return words.size() > 1 ? line.substr(size_t(words[1].data() - line.data())) : "";
    };
    if (keyword == "dataset") {
      if (words.size() != 2 || lowerAscii(words[1]) != "structured_points")
        failLine("only DATASET STRUCTURED_POINTS (image data) is read, got " + quotedExcerpt(line));
      dataset_ = true;
    } else if (!dataset_) {
      failLine("expected DATASET STRUCTURED_POINTS, got " + quotedExcerpt(line));
    } else if (keyword == "dimensions") {
      const SizesText parsed = parseSizesText(rest());
      if (!parsed.problem.empty()) failLine("DIMENSIONS: " + parsed.problem);
      header_.sizes = parsed.sizes;
    } else if (keyword == "spacing" || keyword == "aspect_ratio") {
      header_.spacing = spacing(line, words);
    } else if (keyword == "origin") {
      glm::dvec3 origin;
      for (int axis = 0; axis < 3; ++axis) {
        const auto n = words.size() == 4 ? parseWholeNumber<double>(words[size_t(axis) + 1]) : std::nullopt;
        if (!n || !std::isfinite(*n)) failLine("expected 3 numbers after ORIGIN, got " + quotedExcerpt(line));
        origin[axis] = *n;
      }
      header_.origin = origin;
    } else if (keyword == "field") {
      parseField(words, line);
    } else if (keyword == "point_data") {
      parsePointData(words, line);
    } else if (keyword == "cell_data") {
      failLine("cell data comes before the point data; only point data (one sample per grid point) is read");
    } else if (pointData_ && keyword == "scalars") {
      parseScalars(words, line);
    } else if (pointData_ && keyword == "color_scalars") {
      // VTK writes unsigned char scalars so: in BINARY files one unsigned char per component.
      if (words.size() != 3) failLine("expected COLOR_SCALARS name components, got " + quotedExcerpt(line));
      if (parseWholeNumber<int>(words[2]) != 1)
        failLine("COLOR_SCALARS of " + quotedExcerpt(words[2]) + " components; only one component is read");
      header_.arrayName = std::string(words[1]);
      header_.type = SampleType::UInt8;
      header_.colorScalars = true;
      dataStarts_ = true;
    } else if (pointData_) {
      failLine("the first point attribute is " + quotedExcerpt(words[0]) +
               "; only SCALARS of one component (or a FIELD array of one) is read, and it must come first");
    } else {
      failLine("unknown keyword " + quotedExcerpt(words[0]));
    }
  }

  void parsePointData(const std::vector<std::string_view>& words, std::string_view line) {
    if (header_.sizes.x == 0) failLine("POINT_DATA before DIMENSIONS");
    const auto count = words.size() == 2 ? parseWholeNumber<uint64_t>(words[1]) : std::nullopt;
    const uint64_t samples = uint64_t(header_.sizes.x) * header_.sizes.y * header_.sizes.z;
    if (!count || *count != samples)
      failLine("expected POINT_DATA " + std::to_string(samples) + " (the samples of DIMENSIONS), got " +
               quotedExcerpt(line));
    pointData_ = true;
  }

  SampleType sampleType(std::string_view name) const {
    const auto type = parseVtkType(name);
    if (!type)
      failLine("unsupported type " + quotedExcerpt(name) + "; expected " + std::string(kVtkTypeList));
    return *type;
  }

  void parseScalars(const std::vector<std::string_view>& words, std::string_view line) {
    if (words.size() < 3 || words.size() > 4)
      failLine("expected SCALARS name type [components], got " + quotedExcerpt(line));
    header_.arrayName = std::string(words[1]);
    header_.type = sampleType(words[2]);
    if (words.size() == 4 && parseWholeNumber<int>(words[3]) != 1)
      failLine("SCALARS of " + quotedExcerpt(words[3]) + " components; only one component is read");
    // A LOOKUP_TABLE line may follow; the samples start after it.
    const size_t next = pos_;
    const std::string_view following = takeLine(text_, pos_);
    if (lowerAscii(following.substr(0, 12)) == "lookup_table")
      ++lineNumber_;
    else
      pos_ = next;
    dataStarts_ = true;
  }

  // FIELD name count: `count` arrays, each "name components tuples type" and its samples. Before the point
  // data (the dataset's own fields, a time say) they are skipped; in the point data the first is the volume.
  void parseField(const std::vector<std::string_view>& words, std::string_view line) {
    const auto count = words.size() == 3 ? parseWholeNumber<int64_t>(words[2]) : std::nullopt;
    if (!count || *count < 0 || *count > 1 << 20)
      failLine("expected FIELD name count, got " + quotedExcerpt(line));
    for (int64_t array = 0; array < *count; ++array) {
      const std::string_view arrayLine = nextLine();
      const auto fields = splitWords(trimBlanks(arrayLine));
      const auto components = fields.size() == 4 ? parseWholeNumber<uint64_t>(fields[1]) : std::nullopt;
      const auto tuples = fields.size() == 4 ? parseWholeNumber<uint64_t>(fields[2]) : std::nullopt;
      if (!components || !tuples || *components == 0 || *components > 1u << 20 || *tuples > uint64_t(1) << 40)
        failLine("expected a FIELD array 'name components tuples type', got " + quotedExcerpt(arrayLine));
      if (pointData_) {
        const uint64_t samples = uint64_t(header_.sizes.x) * header_.sizes.y * header_.sizes.z;
        if (*components != 1 || *tuples != samples)
          failLine("the point data's first FIELD array " + quotedExcerpt(fields[0]) + " has " +
                   std::to_string(*components) + " components of " + std::to_string(*tuples) +
                   " tuples; only one component per point is read");
        header_.arrayName = std::string(fields[0]);
        header_.type = sampleType(fields[3]);
        dataStarts_ = true;
        return;
      }
      // The dataset's own field: its samples, then the line end (and VTK 9's METADATA, ended by a blank
      // line).
      const uint64_t values = *components * *tuples;
      const SampleType type = sampleType(fields[3]);
      if (header_.ascii) {
        if (!skipNumbers(values))
          failLine("the FIELD array " + quotedExcerpt(fields[0]) + " ends past the header");
      } else {
        const uint64_t bytes = values * bytesPerSample(type);
        if (bytes > text_.size() - pos_)
          failLine("the FIELD array " + quotedExcerpt(fields[0]) + " ends past the header");
        pos_ += size_t(bytes);
      }
      nextLine();
      const size_t next = pos_;
      if (lowerAscii(trimBlanks(takeLine(text_, pos_))) == "metadata") {
        ++lineNumber_;
        while (pos_ < text_.size() && !trimBlanks(nextLine()).empty()) {
        }
      } else {
        pos_ = next;
      }
    }
  }

  // Moves past `count` numbers of ASCII text (words between blanks and line ends), to the end of the last;
  // false when the text ends first.
  bool skipNumbers(uint64_t count) {
    for (uint64_t i = 0; i < count; ++i) {
      while (pos_ < text_.size() && isBlank(text_[pos_])) lineNumber_ += text_[pos_++] == '\n';
      if (pos_ >= text_.size()) return false;
      while (pos_ < text_.size() && !isBlank(text_[pos_])) ++pos_;
    }
    return true;
  }

  std::string_view text_;
  const std::string& fileName_;
  size_t pos_ = 0;
  size_t lineNumber_ = 0;
  VtkHeader header_;
  bool dataset_ = false, pointData_ = false, dataStarts_ = false;
};

}  // namespace

VtkHeader parseVtkHeader(std::string_view text, const std::string& fileName) {
  return VtkHeaderParser(text, fileName).parse();
}

}  // namespace ropecast
