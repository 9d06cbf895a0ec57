// Input files: small text inputs are read whole; what is not a regular file, or is larger than such an input
// can be, is refused with a message that names it.
#include "core/input_file.h"

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/temporary_file.h"

namespace ropecast {
namespace {

std::string readError(const std::string& path, size_t maxBytes = kMaxTextInputBytes) {
  try {
    readTextInput(path, "the test input " + path, maxBytes);
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(InputFile, ReadsARegularFileWhole) {
  const TemporaryFolder folder("ropecast-test");
  const std::string path = (folder.path() / "a.json").string();
  std::ofstream(path) << "{\"points\": []}\n";
  EXPECT_EQ(readTextInput(path, "a"), "{\"points\": []}\n");
  EXPECT_NO_THROW(requireRegularFile(path, "a"));
}

TEST(InputFile, RefusesWhatIsNotARegularFileWithoutOpeningIt) {
  const TemporaryFolder folder("ropecast-test");
  const std::string fifo = (folder.path() / "fifo").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(readError(fifo).find("the test input " + fifo + ": not a regular file"), std::string::npos);
  EXPECT_NE(readError("/dev/zero").find("not a regular file"), std::string::npos);
  EXPECT_NE(readError(folder.path().string()).find("a folder"), std::string::npos);
  EXPECT_NE(readError((folder.path() / "missing").string()).find("cannot open"), std::string::npos);
  EXPECT_THROW(requireRegularFile(fifo, "fifo"), Error);
}

TEST(InputFile, RefusesAFileLargerThanTheLimit) {
  const TemporaryFolder folder("ropecast-test");
  const std::string path = (folder.path() / "big.json").string();
  std::ofstream(path) << std::string(3u << 20, ' ');
  EXPECT_NE(readError(path, size_t(2) << 20).find("more than the 2 MiB"), std::string::npos);
  EXPECT_EQ(readTextInput(path, "big", size_t(4) << 20).size(), size_t(3) << 20);
}

}  // namespace
}  // namespace ropecast
