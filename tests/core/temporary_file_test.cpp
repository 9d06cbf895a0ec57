// Temporary outputs: a file appears under its name only when committed, and a temporary folder goes away with
// its files.
#include "core/temporary_file.h"

#include <filesystem>
#include <fstream>
#include <span>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "tests/common/temp_dir.h"

namespace ropecast {
namespace {

TEST(TemporaryFile, TheOutputAppearsOnlyWhenCommitted) {
  const TemporaryFolder folder("ropecast-test");
  const std::filesystem::path out = folder.path() / "out.txt";
  const std::string text = "complete";
  {
    TemporaryFile dropped(out, "test");
    dropped.writeAt(0, std::as_bytes(std::span(text)));
  }
  EXPECT_TRUE(std::filesystem::is_empty(folder.path()));  // dropped without commit: nothing left
  TemporaryFile file(out, "test");
  EXPECT_NE(file.path(), out);
  EXPECT_EQ(file.path().parent_path(), out.parent_path());  // beside the output: the rename stays on one disk
  file.writeAt(0, std::as_bytes(std::span(text)));
  EXPECT_FALSE(std::filesystem::exists(out));
  file.commit();
  EXPECT_EQ(test::readBytes(out), text);
  EXPECT_FALSE(std::filesystem::exists(file.path()));
}

TEST(TemporaryFile, AnUnwritableFolderIsAnErrorNamingTheOutput) {
  try {
    TemporaryFile file("/nonexistent-folder/out.png", "test");
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("test: cannot create output '/nonexistent-folder/out.png'"),
              std::string::npos)
        << e.what();
  }
}

TEST(TemporaryFile, AnOutputNameAsLongAsAFileNameMayBeIsWritten) {
  const TemporaryFolder folder("ropecast-test");
  const std::filesystem::path out = folder.path() / (std::string(250, 'n') + ".png");  // 254 bytes
  const std::string text = "complete";
  TemporaryFile file(out, "test");
  EXPECT_EQ(file.path().parent_path(), out.parent_path());
  file.writeAt(0, std::as_bytes(std::span(text)));
  file.commit();
  EXPECT_EQ(test::readBytes(out), text);
}

// Refused before any work is done: the temporary's shortened name would have been created, and the rename at
// the end would fail.
TEST(TemporaryFile, AnOutputNameLongerThanAFileNameMayBeIsRefusedAtOnce) {
  const TemporaryFolder folder("ropecast-test");
  const std::filesystem::path out = folder.path() / (std::string(252, 'n') + ".png");  // 256 bytes
  EXPECT_NE(outputFileProblem(out).find("its file name is 256 bytes long"), std::string::npos)
      << outputFileProblem(out);
  EXPECT_THROW(TemporaryFile(out, "test"), Error);
  EXPECT_TRUE(std::filesystem::is_empty(folder.path()));
}

TEST(TemporaryFolder, GoesAwayWithItsFiles) {
  std::filesystem::path kept;
  {
    const TemporaryFolder folder("ropecast-test");
    kept = folder.path();
    EXPECT_TRUE(std::filesystem::is_directory(kept));
    EXPECT_EQ(kept.parent_path(), std::filesystem::temp_directory_path());
    EXPECT_EQ(kept.filename().string().rfind("ropecast-test-", 0), 0u) << kept;
    std::ofstream(kept / "a.log") << "log";
    std::ofstream(kept / "b.png") << "image";
  }
  EXPECT_FALSE(std::filesystem::exists(kept));
}

TEST(TemporaryFolder, InAGivenFolderWithAPrefixTooLongForAName) {
  const TemporaryFolder parent("ropecast-test");
  std::filesystem::path kept;
  {
    const TemporaryFolder folder(parent.path(), std::string(300, 'p'));
    kept = folder.path();
    EXPECT_TRUE(std::filesystem::is_directory(kept));
    EXPECT_EQ(kept.parent_path(), parent.path());
    EXPECT_LE(kept.filename().string().size(), 255u);
  }
  EXPECT_FALSE(std::filesystem::exists(kept));
}

}  // namespace
}  // namespace ropecast
