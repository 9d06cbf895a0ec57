#include "core/input_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace ropecast {
namespace {

std::string statProblem(const struct stat& st) {
  if (S_ISDIR(st.st_mode)) return "a folder, expected a file";
  if (!S_ISREG(st.st_mode)) return "not a regular file (a pipe, device or socket), expected a file";
  return "";
}

}  // namespace

void requireRegularFile(const std::string& path, const std::string& what) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw Error(what + ": cannot open: " + std::strerror(errno));
  if (const std::string problem = statProblem(st); !problem.empty()) throw Error(what + ": " + problem);
}

std::string readTextInput(const std::string& path, const std::string& what, size_t maxBytes) {
  requireRegularFile(path, what);
  // O_NONBLOCK: should the path have become a FIFO since the check, opening it must not wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw Error(what + ": cannot open: " + std::strerror(errno));
  struct stat st {};
  std::string problem =
      ::fstat(fd, &st) != 0 ? std::string("cannot stat: ") + std::strerror(errno) : statProblem(st);
  if (problem.empty() && uint64_t(st.st_size) > maxBytes)
    problem = std::to_string(st.st_size) + " bytes, more than the " + std::to_string(maxBytes >> 20) +
              " MiB such a file can be";
  std::string text;
  if (problem.empty()) {
    text.resize(size_t(st.st_size));
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t n = ::read(fd, text.data() + done, text.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) {
        problem = std::string("cannot read: ") + std::strerror(errno);
        break;
      }
      if (n == 0) break;  // shrank while read: take what is there
      done += size_t(n);
    }
    text.resize(done);
  }
  ::close(fd);
  if (!problem.empty()) throw Error(what + ": " + problem);
  return text;
}

}  // namespace ropecast
