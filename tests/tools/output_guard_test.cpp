// OutputGuard: an output that is an input (by name, symlink or hard link, or inside an input folder or glob),
// another output, or an existing folder, is refused naming the options; new files pass.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>

#include "core/error.h"
#include "tests/common/temp_dir.h"
#include "tools/output_guard.h"

namespace ropecast::tools {
namespace {

namespace fs = std::filesystem;

class OutputGuardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir = test::freshTempDir();
    input = (dir / "scan_4x4x4_uint8.raw").string();
    test::writeText(input, std::string(64, 'x'));
  }
  std::string problemWith(const std::string& output) const {
    OutputGuard guard("convert");
    guard.addInput("the input", input);
    guard.addOutput("-o", output);
    return guard.problem();
  }
  fs::path dir;
  std::string input;
};

TEST_F(OutputGuardTest, FileIdentityIsEqualExactlyForOneFile) {
  // Not written yet: the same absolute name.
  const std::string a = (dir / "cams.json").string();
  EXPECT_EQ(fileIdentity(a), fileIdentity((dir / "." / "x" / ".." / "cams.json").string()));
  EXPECT_NE(fileIdentity(a), fileIdentity((dir / "other.json").string()));
  // Existing: the same file through a link.
  fs::create_symlink(input, dir / "link.raw");
  EXPECT_EQ(fileIdentity(input), fileIdentity((dir / "link.raw").string()));
  EXPECT_NE(fileIdentity(input), fileIdentity(a));
}

TEST_F(OutputGuardTest, ANewFilePasses) {
  EXPECT_EQ(problemWith((dir / "scan.rcast").string()), "");
  OutputGuard guard("render");
  guard.addInput("the input", "procedural:sphere:64");
  guard.addOutput("-o", (dir / "a.png").string());
  guard.addOutput("--exr", (dir / "a.exr").string());
  EXPECT_NO_THROW(guard.check());
}

TEST_F(OutputGuardTest, AFolderIsRefusedAsAnOutput) {
  EXPECT_EQ(problemWith(dir.string()),
            "convert: -o " + dir.string() +
                ": a folder; expected the name of a file to write, nothing was written");
  OutputGuard guard("render");
  guard.addOutput("-o", (dir / "a.png").string());
  guard.addOutput("--stats", dir.string());
  EXPECT_THROW(guard.check(), Error);
}

TEST_F(OutputGuardTest, TheInputItselfIsRefusedNamingBoth) {
  EXPECT_EQ(problemWith(input), "convert: -o " + input + ": the same file as the input " + input +
                                    "; refusing to overwrite an input, nothing was written");
  OutputGuard guard("convert");
  guard.addInput("the input", input);
  guard.addOutput("-o", input);
  EXPECT_THROW(guard.check(), Error);
}

TEST_F(OutputGuardTest, AnotherSpellingOfTheInputIsRefused) {
  EXPECT_NE(problemWith((dir / "." / "scan_4x4x4_uint8.raw").string()), "");
  const fs::path cwd = fs::current_path();
  fs::current_path(dir);
  EXPECT_NE(problemWith("scan_4x4x4_uint8.raw"), "");
  fs::current_path(cwd);
}

TEST_F(OutputGuardTest, ASymlinkToTheInputIsRefused) {
  fs::create_symlink(input, dir / "link.raw");
  const std::string problem = problemWith((dir / "link.raw").string());
  EXPECT_NE(problem.find("the same file as the input"), std::string::npos) << problem;
  EXPECT_NE(problem.find("through a link"), std::string::npos) << problem;
}

TEST_F(OutputGuardTest, AHardLinkToTheInputIsRefused) {
  fs::create_hard_link(input, dir / "hard.raw");
  EXPECT_NE(problemWith((dir / "hard.raw").string()), "");
}

TEST_F(OutputGuardTest, AFolderOfSymlinksIsFollowed) {
  fs::create_directories(dir / "real");
  fs::create_directory_symlink(dir, dir / "real" / "up");
  EXPECT_NE(problemWith((dir / "real" / "up" / "scan_4x4x4_uint8.raw").string()), "");
}

TEST_F(OutputGuardTest, AFileInAnInputFolderOrGlobIsRefused) {
  test::writeText(dir / "slices" / "s0.png", "a");
  test::writeText(dir / "slices" / "s1.png", "b");
  for (const std::string& source : {(dir / "slices").string(), (dir / "slices" / "s*.png").string()}) {
    OutputGuard guard("convert");
    guard.addVolumeInput("the input", source);
    guard.addOutput("-o", (dir / "slices" / "s1.png").string());
    EXPECT_NE(guard.problem(), "") << source;
    OutputGuard fresh("convert");
    fresh.addVolumeInput("the input", source);
    fresh.addOutput("-o", (dir / "slices" / "volume.rcast").string());
    EXPECT_EQ(fresh.problem(), "") << source;
  }
}

// A folder given where a file is read (render's store) is not a volume: the files in it are not inputs, and
// the reader says what is wrong ("a folder, expected a file"), not the guard.
TEST_F(OutputGuardTest, AFolderGivenForAFileInputDoesNotClaimItsFiles) {
  test::writeText(dir / "renders" / "x.png", "an earlier render");
  OutputGuard guard("render");
  guard.addInput("the input", (dir / "renders").string());
  guard.addOutput("-o", (dir / "renders" / "x.png").string());
  EXPECT_EQ(guard.problem(), "");
}

TEST_F(OutputGuardTest, TwoOutputsOnOneFileAreRefusedNamingBoth) {
  OutputGuard guard("render");
  guard.addInput("the input", input);
  const std::string exr = (dir / "a.exr").string();
  guard.addOutput("--exr", exr);
  guard.addOutput("--depth", (dir / "sub" / ".." / "a.exr").string());
  EXPECT_EQ(guard.problem(),
            "render: --exr " + exr + " and --depth " + (dir / "sub" / ".." / "a.exr").string() +
                " are the same file (through a link or another name): give each output its own "
                "file; nothing was written");
}

TEST_F(OutputGuardTest, ASeriesMeetsInputsAndOutputs) {
  const auto frames = [](const std::string& name) {
    return name.starts_with("out_") && name.ends_with(".png");
  };
  fs::create_hard_link(input, dir / "out_0003.png");
  OutputGuard guard("render");
  guard.addInput("the input", input);
  guard.addOutputSeries("--every", dir.string(), "out_NNNN.png", frames);
  EXPECT_NE(guard.problem().find("the same file as the input"), std::string::npos) << guard.problem();

  OutputGuard outputs("render");
  outputs.addOutput("--stats", (dir / "out_0007.png").string());
  outputs.addOutputSeries("--every", dir.string(), "out_NNNN.png", frames);
  EXPECT_NE(outputs.problem().find("are the same file"), std::string::npos) << outputs.problem();
}

TEST(VolumeSpecFiles, NameTheHeaderAndTheDetachedDataOfNrrd) {
  const fs::path dir = test::freshTempDir();
  test::writeText(dir / "v.nhdr",
                  "NRRD0004\ntype: uint8\ndimension: 3\nsizes: 2 2 2\nencoding: raw\ndata file: v.raw\n");
  EXPECT_EQ(volumeSpecFiles((dir / "v.nhdr").string()),
            (std::vector<std::string>{(dir / "v.nhdr").string(), (dir / "v.raw").string()}));
  EXPECT_TRUE(volumeSpecFiles("procedural:sphere:64").empty());
  EXPECT_EQ(volumeSpecFiles("a.raw"), std::vector<std::string>{"a.raw"});
}

TEST(VolumeSpecFiles, NameTheDataFilesOfMetaImageAndNiftiPairs) {
  const fs::path dir = test::freshTempDir();
  test::writeText(dir / "v.mhd",
                  "NDims = 3\nDimSize = 2 2 2\nElementType = MET_UCHAR\nElementDataFile = d.raw\n");
  EXPECT_EQ(volumeSpecFiles((dir / "v.mhd").string()),
            (std::vector<std::string>{(dir / "v.mhd").string(), (dir / "d.raw").string()}));

  // A NIfTI-1 header of a header/image pair ("ni1"): 2x2x2 uint8 samples from the .img's first byte.
  std::string header(348, '\0');
  const auto put16 = [&](size_t at, int16_t v) { std::memcpy(header.data() + at, &v, 2); };
  const int32_t size = 348;
  std::memcpy(header.data(), &size, 4);
  for (size_t i = 0; i < 4; ++i) put16(40 + 2 * i, i == 0 ? 3 : 2);
  put16(70, 2);  // datatype uint8
  put16(72, 8);  // bitpix
  std::memcpy(header.data() + 344, "ni1", 4);
  test::writeText(dir / "p.hdr", header);
  test::writeText(dir / "p.img", std::string(8, 'x'));
  const std::vector<std::string> pair{(dir / "p.hdr").string(), (dir / "p.img").string()};
  EXPECT_EQ(volumeSpecFiles(pair[0]), pair);
  EXPECT_EQ(volumeSpecFiles(pair[1]), (std::vector<std::string>{pair[1], pair[0]}));
}

}  // namespace
}  // namespace ropecast::tools
