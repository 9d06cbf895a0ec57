// Tests of the DICOM structure check that runs before GDCM reads a file: whole files pass (single-frame,
// enhanced with sequences of undefined length), and files cut short (within the meta group, within a
// sequence, within the pixel data, right after the meta group) or with an undefined value representation
// are refused with the reason, not handed to GDCM, which stops the process on some of them.
#include "store/dicom_structure.h"

#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "tests/store/store_test_util.h"
#include "tests/store/testutil_dicom.h"

namespace ropecast {
namespace {

using testing::DicomSliceSpec;
using testing::TempDir;

std::string bytesOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// `bytes` cut to `size`, written beside them, and its problem.
std::string problemCutTo(const TempDir& dir, const std::string& bytes, size_t size) {
  const std::string path = dir.file("cut.dcm");
  testing::writeFile(path, std::string_view(bytes).substr(0, size));
  return dicomStructureProblem(path);
}

TEST(DicomStructure, WholeFilesPassAndFilesCutShortAreRefused) {
  const TempDir dir;
  DicomSliceSpec plain;
  plain.stored.assign(size_t(plain.columns) * plain.rows, 7);
  writeDicomSlice(dir.file("plain.dcm"), plain);
  DicomSliceSpec enhanced = plain;
  enhanced.frames = 3;
  enhanced.stored.assign(size_t(plain.columns) * plain.rows * 3, 7);
  enhanced.framePositions = {glm::dvec3(0, 0, 0), glm::dvec3(0, 0, 1), glm::dvec3(0, 0, 2)};
  writeDicomSlice(dir.file("enhanced.dcm"), enhanced);
  EXPECT_EQ(dicomStructureProblem(dir.file("plain.dcm")), "");
  EXPECT_EQ(dicomStructureProblem(dir.file("enhanced.dcm")), "");

  for (const char* name : {"plain.dcm", "enhanced.dcm"}) {
    const std::string bytes = bytesOf(dir.file(name));
    SCOPED_TRACE(name);
    // The last byte of the pixel data, whose element declares more than is left.
    const std::string pixels = problemCutTo(dir, bytes, bytes.size() - 1);
    EXPECT_NE(pixels.find("the element (7FE0,0010)"), std::string::npos) << pixels;
    EXPECT_NE(pixels.find("past the end of its file"), std::string::npos) << pixels;
    EXPECT_NE(problemCutTo(dir, bytes, 140).find("within the file meta group"), std::string::npos);
    EXPECT_NE(problemCutTo(dir, bytes, 100).find("no DICM signature"), std::string::npos);
    // Every cut is refused or ends between two whole elements of the data set (which GDCM reads as a data
    // set without them): none is read as whole with a value cut short.
    size_t refused = 0;
    for (size_t size = 132; size < bytes.size(); ++size) refused += !problemCutTo(dir, bytes, size).empty();
    EXPECT_GT(refused, (bytes.size() - 132) * 9 / 10);
  }

  // Cut within the per-frame functional groups: a sequence of undefined length without its delimiter.
  const std::string bytes = bytesOf(dir.file("enhanced.dcm"));
  const size_t perFrame = bytes.find(std::string("\x00\x52\x30\x92", 4));
  ASSERT_NE(perFrame, std::string::npos);
  const std::string sequence = problemCutTo(dir, bytes, perFrame + 40);
  EXPECT_NE(sequence.find("the file ends within"), std::string::npos) << sequence;

  // A value representation the standard does not define.
  std::string badVr = bytes;
  badVr[perFrame + 4] = 'Q';
  badVr[perFrame + 5] = 'Q';
  testing::writeFile(dir.file("vr.dcm"), badVr);
  const std::string vr = dicomStructureProblem(dir.file("vr.dcm"));
  EXPECT_NE(vr.find("the element (5200,9230) at byte " + std::to_string(perFrame) +
                    " has no value representation the standard defines ('QQ')"),
            std::string::npos)
      << vr;
}

}  // namespace
}  // namespace ropecast
