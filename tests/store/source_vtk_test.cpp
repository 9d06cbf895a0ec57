// Tests of the legacy VTK header parser and source: BINARY and ASCII STRUCTURED_POINTS of every type read,
// with and without a lookup table line, unsigned char ones as VTK writes them (COLOR_SCALARS), keywords in
// any order and case, the dataset's own FIELD data (and VTK 9's METADATA) skipped, a point-data FIELD array
// as the volume, ASCII slabs read out of order, and each unsupported or malformed file giving an error that
// names the file and the line (or the sample).
#include <cmath>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "store/source_vtk.h"
#include "store/volume_source.h"
#include "store/vtk_header.h"
#include "tests/store/store_test_util.h"

namespace ropecast {
namespace {

using testing::errorOf;
using testing::expectHeadersRefused;
using testing::expectVolume;
using testing::fileBytes;
using testing::readSlab;
using testing::RefusedHeader;
using testing::samplePattern;
using testing::TempDir;
using testing::writeFile;

constexpr size_t kVtkSamples = 9 * 6 * 5;

// A header as VTK's writer leaves one for a 9x6x5 volume, up to the samples.
std::string vtkHeader(const std::string& type, const std::string& attribute = "") {
  return "# vtk DataFile Version 3.0\nwritten by a test\nBINARY\nDATASET STRUCTURED_POINTS\n"
         "DIMENSIONS 9 6 5\nSPACING 0.5 0.75 2\nORIGIN -10 0 3.5\nPOINT_DATA 270\n" +
         (attribute.empty() ? "SCALARS ImageFile " + type + "\nLOOKUP_TABLE default\n" : attribute);
}

// `values` as an ASCII file writes them: `perLine` numbers a line, floats with the digits that give them
// back.
template <typename T>
std::string asciiNumbers(const std::vector<T>& values, size_t perLine = 9, const char* lineEnd = "\n") {
  std::ostringstream text;
  text.precision(std::is_same_v<T, float> ? 9 : 17);
  for (size_t i = 0; i < values.size(); ++i) {
    if constexpr (sizeof(T) == 1)
      text << int(values[i]);
    else
      text << values[i];
    text << ((i + 1) % perLine == 0 || i + 1 == values.size() ? lineEnd : " ");
  }
  return text.str();
}

std::string asciiHeader(const std::string& type, const std::string& attribute = "") {
  std::string header = vtkHeader(type, attribute);
  header.replace(header.find("BINARY"), 6, "ASCII");
  return header;
}

TEST(SourceVtk, StructuredPointsOfEveryTypeInBinaryAndAscii) {
  TempDir dir;
  auto check = [&](auto tag, const std::string& vtkType, SampleType type) {
    using T = decltype(tag);
    const auto values = samplePattern<T>(kVtkSamples);
    const std::string binary = dir.file(vtkType + ".vtk"), ascii = dir.file("ascii_" + vtkType + ".vtk");
    writeFile(binary, vtkHeader(vtkType) + fileBytes(values, /*bigEndian=*/true) + "\n");
    writeFile(ascii, asciiHeader(vtkType) + asciiNumbers(values));
    for (const std::string& path : {binary, ascii}) {
      expectVolume(*openVolumeSource(path),
                   {{9, 6, 5}, type, {0.5, 0.75, 2.0}, "vtk:" + path + " (ImageFile)"}, values);
      EXPECT_EQ(openVolumeSource(path)->info().origin, glm::dvec3(-10.0, 0.0, 3.5)) << path;  // ORIGIN
    }
  };
  check(int8_t{}, "char", SampleType::Int8);
  check(uint8_t{}, "unsigned_char", SampleType::UInt8);
  check(int16_t{}, "short", SampleType::Int16);
  check(uint16_t{}, "unsigned_short", SampleType::UInt16);
  check(int32_t{}, "int", SampleType::Int32);
  check(uint32_t{}, "unsigned_int", SampleType::UInt32);
  check(float{}, "float", SampleType::Float32);
  check(double{}, "double", SampleType::Float64);
  check(uint16_t{}, "vtktypeuint16", SampleType::UInt16);
}

TEST(SourceVtk, LayoutsWritersLeave) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kVtkSamples);
  const std::string data = fileBytes(values, true);

  // Lower-case keywords in another order, ASPECT_RATIO, SCALARS with its component count and no lookup table.
  const std::string plain = dir.file("plain.vtk");
  writeFile(plain,
            "# vtk DataFile Version 2.0\ntitle\nbinary\ndataset structured_points\norigin 0 0 0\n"
            "aspect_ratio 1 2 3\n\ndimensions 9 6 5\npoint_data 270\nscalars density short 1\n" +
                data);
  auto source = openVolumeSource(plain);
  EXPECT_EQ(source->info().spacing, glm::dvec3(1.0, 2.0, 3.0));
  EXPECT_EQ(readSlab<int16_t>(*source, 0, 5), values);

  // ParaView's time as the dataset's FIELD data before the geometry, with VTK 9's METADATA after it; CRLF.
  const std::string timed = dir.file("timed.vtk");
  writeFile(timed,
            "# vtk DataFile Version 5.1\r\ntitle\r\nBINARY\r\nDATASET STRUCTURED_POINTS\r\n"
            "FIELD FieldData 2\r\nTIME 1 1 double\r\n" +
                fileBytes(std::vector<double>{2.5}, true) +
                "\r\nMETADATA\r\nINFORMATION 0\r\n\r\nCYCLE 1 2 int\r\n" +
                fileBytes(std::vector<int32_t>{4, 5}, true) +
                "\r\nDIMENSIONS 9 6 5\r\nSPACING 1 1 1\r\nORIGIN 0 0 0\r\nPOINT_DATA 270\r\n"
                "SCALARS ImageFile short\r\nLOOKUP_TABLE default\r\n" +
                data);
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(timed), 0, 5), values);

  // Unsigned char scalars as VTK's writer leaves them.
  const auto bytes = samplePattern<uint8_t>(kVtkSamples);
  const std::string color = dir.file("color.vtk");
  writeFile(color, vtkHeader("", "COLOR_SCALARS RT 1\n") + fileBytes(bytes));
  auto colorSource = openVolumeSource(color);
  EXPECT_EQ(colorSource->info().type, SampleType::UInt8);
  EXPECT_EQ(readSlab<uint8_t>(*colorSource, 0, 5), bytes);

  // The point data as a FIELD array of one component.
  const std::string field = dir.file("field.vtk");
  writeFile(field, vtkHeader("", "FIELD FieldData 2\nDensity 1 270 short\n") + data);
  auto fieldSource = openVolumeSource(field);
  EXPECT_EQ(fieldSource->info().description, "vtk:" + field + " (Density)");
  EXPECT_EQ(readSlab<int16_t>(*fieldSource, 0, 5), values);
}

TEST(SourceVtk, AsciiLayoutsWritersLeave) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kVtkSamples);

  // One number a line with CRLF, then a slab before the last one read: the reader starts over.
  const std::string crlf = dir.file("crlf.vtk");
  writeFile(crlf, asciiHeader("short") + asciiNumbers(values, 1, "\r\n"));
  auto source = openVolumeSource(crlf);
  const std::vector<int16_t> last = readSlab<int16_t>(*source, 3, 2),
                             first = readSlab<int16_t>(*source, 0, 3);
  EXPECT_EQ(first, std::vector<int16_t>(values.begin(), values.begin() + 3 * 54));
  EXPECT_EQ(last, std::vector<int16_t>(values.begin() + 3 * 54, values.end()));

  // All on one line with tabs, no line end after the last; the dataset's FIELD data before, in ASCII.
  const std::string oneLine = dir.file("one_line.vtk");
  std::string numbers = asciiNumbers(values, kVtkSamples, "");
  for (char& c : numbers) c = c == ' ' ? '\t' : c;
  writeFile(oneLine,
            "# vtk DataFile Version 5.1\ntitle\nASCII\nDATASET STRUCTURED_POINTS\nFIELD FieldData 2\n"
            "TIME 1 1 double\n2.5\nMETADATA\nINFORMATION 0\n\nCYCLE 1 2 int\n4 5\n"
            "DIMENSIONS 9 6 5\nSPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 270\nSCALARS ImageFile short\n"
            "LOOKUP_TABLE default\n" +
                numbers);
  EXPECT_EQ(readSlab<int16_t>(*openVolumeSource(oneLine), 0, 5), values);

  // Unsigned char scalars as VTK writes them in ASCII: COLOR_SCALARS, fractions of 255 with six digits.
  const auto bytes = samplePattern<uint8_t>(kVtkSamples);
  std::vector<double> fractions;
  for (uint8_t b : bytes) fractions.push_back(std::round(b / 255.0 * 1e6) / 1e6);
  const std::string color = dir.file("ascii_color.vtk");
  std::ostringstream text;
  for (double f : fractions) text << f << "\n";
  writeFile(color, asciiHeader("", "COLOR_SCALARS RT 1\n") + text.str());
  auto colorSource = openVolumeSource(color);
  EXPECT_EQ(colorSource->info().type, SampleType::UInt8);
  EXPECT_EQ(readSlab<uint8_t>(*colorSource, 0, 5), bytes);
}

TEST(SourceVtk, AsciiFilesLongerThanTheReadBufferAreReadWhole) {
  // 2.9 MB of numbers: several refills of the reader's 1 MiB buffer, numbers cut at their ends.
  TempDir dir;
  const glm::u32vec3 dims{64, 64, 64};
  std::vector<int32_t> values(size_t(dims.x) * dims.y * dims.z);
  for (size_t i = 0; i < values.size(); ++i) values[i] = int32_t(i * 2654435761u % 2000000000u) - 1000000000;
  const std::string path = dir.file("big.vtk");
  writeFile(path,
            "# vtk DataFile Version 3.0\nbig\nASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 64 64 64\n"
            "POINT_DATA 262144\nSCALARS v int\n" +
                asciiNumbers(values, 7));
  auto source = openVolumeSource(path);
  EXPECT_EQ(readSlab<int32_t>(*source, 0, 64), values);
  const std::vector<int32_t> again = readSlab<int32_t>(*source, 40, 3);  // after the end: from the start
  EXPECT_EQ(again, std::vector<int32_t>(values.begin() + 40 * 4096, values.begin() + 43 * 4096));
}

TEST(SourceVtk, AsciiSamplesThatAreNotThereOrNotOfTheTypeNameTheFileAndSample) {
  TempDir dir;
  const auto values = samplePattern<int16_t>(kVtkSamples);
  std::vector<std::string> numbers;
  for (int16_t v : values) numbers.push_back(std::to_string(v));
  const auto fileWith = [&](const std::string& name, const std::string& header,
                            const std::vector<std::string>& words) {
    std::string text = header;
    for (const std::string& w : words) text += w + "\n";
    const std::string path = dir.file(name);
    writeFile(path, text);
    return path;
  };
  struct Case {
    std::string name, header;
    std::vector<std::string> words;
    std::string expected;
  };
  std::vector<std::string> shortOfOne(numbers.begin(), numbers.end() - 1);
  std::vector<std::string> word = numbers, fraction = numbers, outside = numbers, huge = numbers;
  word[17] = "abc";
  fraction[40] = "1.5";
  outside[100] = "40000";
  huge[3] = std::string(300, '7');
  std::vector<std::string> colors(kVtkSamples, "0.5");
  colors[9] = "1.5";
  const std::vector<Case> cases = {
      {"short.vtk", asciiHeader("short"), shortOfOne, "ends after 269 of its 270 samples"},
      {"word.vtk", asciiHeader("short"), word, "sample 17 is 'abc', not a int16"},
      {"fraction.vtk", asciiHeader("short"), fraction, "sample 40 is '1.5', not a int16"},
      {"outside.vtk", asciiHeader("short"), outside, "sample 100 is '40000', not a int16"},
      {"long.vtk", asciiHeader("short"), huge, "sample 3 is a word of more than 256 characters"},
      {"color.vtk", asciiHeader("", "COLOR_SCALARS RT 1\n"), colors,
       "sample 9 is '1.5', not a uint8 once multiplied by 255"},
  };
  for (const Case& c : cases) {
    const std::string path = fileWith(c.name, c.header, c.words);
    std::string message;  // the header is fine: the samples fail as they are read
    try {
      readSlab<int16_t>(*openVolumeSource(path), 0, 5);
    } catch (const Error& e) {
      message = e.what();
    }
    EXPECT_NE(message.find("legacy VTK file " + path), std::string::npos) << c.name << ": " << message;
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.name << ": " << message;
  }
}

TEST(SourceVtk, UnsupportedAndMalformedFilesNameTheFileAndLine) {
  const std::string good = vtkHeader("short");
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::vector<RefusedHeader> cases = {
      {"no magic", "vtk file\n" + good, "expected the line '# vtk DataFile Version x.x'"},
      {"neither", replaced("BINARY", "TEXT"), "expected ASCII or BINARY"},
      {"polydata", replaced("STRUCTURED_POINTS", "POLYDATA"), "line 4: only DATASET STRUCTURED_POINTS"},
      {"grid", replaced("STRUCTURED_POINTS", "RECTILINEAR_GRID"), "only DATASET STRUCTURED_POINTS"},
      {"two sizes", replaced("DIMENSIONS 9 6 5", "DIMENSIONS 9 6"), "line 5: DIMENSIONS: expected 3"},
      {"zero spacing", replaced("SPACING 0.5 0.75 2", "SPACING 0.5 0 2"), "expected 3 non-zero numbers"},
      {"count", replaced("POINT_DATA 270", "POINT_DATA 271"), "expected POINT_DATA 270"},
      {"cells", replaced("POINT_DATA 270", "CELL_DATA 160"), "cell data comes before the point data"},
      {"vectors", vtkHeader("", "VECTORS v float\n"), "the first point attribute is 'VECTORS'"},
      {"components", vtkHeader("", "SCALARS rgb unsigned_char 3\n"), "only one component is read"},
      {"colors", vtkHeader("", "COLOR_SCALARS rgba 4\n"), "only one component is read"},
      {"field components", vtkHeader("", "FIELD f 1\nvelocity 3 270 float\n"), "has 3 components"},
      {"bit", vtkHeader("bit"), "unsupported type 'bit'"},
      {"long", vtkHeader("long"), "unsupported type 'long'"},
      {"64-bit", vtkHeader("vtktypeint64"), "unsupported type 'vtktypeint64'"},
      {"unknown keyword", replaced("ORIGIN", "CENTER"), "unknown keyword 'CENTER'"},
      {"short origin", replaced("ORIGIN -10 0 3.5", "ORIGIN -10 0"), "expected 3 numbers after ORIGIN"},
      {"no samples", "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 9 6 5\n",
       "ends before the samples"},
      {"field past the end", replaced("DIMENSIONS", "FIELD FieldData 1\nTIME 1 100000 double\nDIMENSIONS"),
       "ends past the header"},
  };
  expectHeadersRefused(cases, "/some/dir/bad.vtk",
                       [](const std::string& h, const std::string& f) { parseVtkHeader(h, f); });

  TempDir dir;
  const std::string data = fileBytes(samplePattern<int16_t>(kVtkSamples), true);
  const std::string truncated = dir.file("truncated.vtk");
  writeFile(truncated, good + data.substr(0, data.size() - 1));
  const std::string message = errorOf(truncated);
  EXPECT_NE(message.find(truncated), std::string::npos) << message;
  EXPECT_NE(message.find("truncated"), std::string::npos) << message;
}

}  // namespace
}  // namespace ropecast
