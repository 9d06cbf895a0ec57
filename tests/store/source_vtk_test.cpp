// Tests of the legacy VTK header parser and source: BINARY STRUCTURED_POINTS of every type read, with and
// without a lookup table line, unsigned char ones as VTK writes them (COLOR_SCALARS), keywords in any order
// and case, the dataset's own FIELD data (and VTK 9's
// METADATA) skipped, a point-data FIELD array as the volume, and each unsupported or malformed file giving an
// error that names the file and the line.
#include <string>
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
using testing::expectVolume;
using testing::fileBytes;
using testing::readSlab;
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

TEST(SourceVtk, StructuredPointsOfEveryType) {
  TempDir dir;
  auto check = [&](auto tag, const std::string& vtkType, SampleType type) {
    using T = decltype(tag);
    const auto values = samplePattern<T>(kVtkSamples);
    const std::string path = dir.file(vtkType + ".vtk");
    writeFile(path, vtkHeader(vtkType) + fileBytes(values, /*bigEndian=*/true) + "\n");
    expectVolume(*openVolumeSource(path), {{9, 6, 5}, type, {0.5, 0.75, 2.0}, "vtk:" + path + " (ImageFile)"},
                 values);
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

TEST(SourceVtk, UnsupportedAndMalformedFilesNameTheFileAndLine) {
  struct Case {
    std::string what, header, expected;
  };
  const std::string good = vtkHeader("short");
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  const std::vector<Case> cases = {
      {"no magic", "vtk file\n" + good, "expected the line '# vtk DataFile Version x.x'"},
      {"ASCII", replaced("BINARY", "ASCII"), "ASCII files are not read"},
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
      {"no samples", "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 9 6 5\n",
       "ends before the samples"},
      {"field past the end", replaced("DIMENSIONS", "FIELD FieldData 1\nTIME 1 100000 double\nDIMENSIONS"),
       "ends past the header"},
  };
  for (const Case& c : cases) {
    try {
      parseVtkHeader(c.header, "/some/dir/bad.vtk");
      ADD_FAILURE() << c.what << ": parsed without error";
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("/some/dir/bad.vtk"), std::string::npos) << c.what << ": " << message;
      EXPECT_NE(message.find(c.expected), std::string::npos) << c.what << ": " << message;
    }
  }

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
