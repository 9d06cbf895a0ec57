#include "core/temporary_file.h"

#include <dirent.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <string_view>
#include <utility>
#include <vector>

#include "core/error.h"

namespace ropecast {

namespace {
std::string errnoText() {
  return std::strerror(errno);
}

// Temporary names readable from a signal handler: a slot is claimed, filled, then published.
struct SignalSlot {
  std::atomic<bool> claimed{false};
  std::atomic<bool> ready{false};
  bool folder = false;  // a folder of files, removed with them
  char path[4096];
};
constexpr int kSignalSlots = 32;
SignalSlot signalSlots[kSignalSlots];

int publishTemporary(const std::string& path, bool folder = false) {
  if (path.size() >= sizeof(SignalSlot::path)) return -1;
  for (int i = 0; i < kSignalSlots; ++i) {
    bool expected = false;
    if (!signalSlots[i].claimed.compare_exchange_strong(expected, true)) continue;
    signalSlots[i].folder = folder;
    std::memcpy(signalSlots[i].path, path.c_str(), path.size() + 1);
    signalSlots[i].ready.store(true);
    return i;
  }
  return -1;  // more than kSignalSlots at once: that one is not removed on a signal
}

void withdrawTemporary(int slot) {
  if (slot < 0) return;
  signalSlots[slot].ready.store(false);
  signalSlots[slot].claimed.store(false);
}

// The files directly in `path`, then the folder, with system calls only (async-signal-safe: no allocation).
void removeFlatFolder(const char* path) {
  const int fd = ::open(path, O_RDONLY | O_DIRECTORY);
  if (fd < 0) return;
  alignas(8) char buffer[4096];
  for (long n; (n = ::syscall(SYS_getdents64, fd, buffer, sizeof buffer)) > 0;) {
    for (long at = 0; at < n;) {
      const auto* entry = reinterpret_cast<const struct dirent64*>(buffer + at);
      if (entry->d_type != DT_DIR) ::unlinkat(fd, entry->d_name, 0);
      at += entry->d_reclen;
    }
  }
  ::close(fd);
  ::rmdir(path);
}

// Children that get the signal too (0: a free slot).
constexpr int kChildSlots = 64;
std::atomic<pid_t> childSlots[kChildSlots];

void removeTemporariesAndDie(int signal) {
  // The children first: their temporaries may lie in a temporary folder of ours.
  for (auto& child : childSlots)
    if (const pid_t pid = child.load(); pid > 0) {
      ::kill(pid, signal == SIGABRT ? SIGTERM : signal);  // our abort is not the child's
      ::kill(pid, SIGCONT);  // a stopped child (Ctrl-Z) would never end, nor this wait for it
    }
  for (auto& child : childSlots)
    if (const pid_t pid = child.load(); pid > 0) ::waitpid(pid, nullptr, 0);
  for (auto& slot : signalSlots) {
    if (!slot.ready.load()) continue;
    if (slot.folder)
      removeFlatFolder(slot.path);
    else
      ::unlink(slot.path);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// `name` with `suffix` after it, `name` shortened so that the two fit in a file name.
std::string fitFileName(std::string name, std::string_view suffix) {
  if (name.size() + suffix.size() > NAME_MAX) name.resize(NAME_MAX - suffix.size());
  return name + std::string(suffix);
}

// Where a write to `output` lands: its symbolic links followed to the name they lead to (which need not
// exist), or why no file should be written there.
struct LinkTarget {
  std::filesystem::path path;
  std::string problem;
};
LinkTarget followLinks(std::filesystem::path path) {
  for (int hops = 0; hops < 40; ++hops) {
    const std::string name = std::filesystem::absolute(path).lexically_normal().string();
    if ((name.starts_with("/dev/") && !name.starts_with("/dev/shm/")) || name.starts_with("/proc/"))
      return {path,
              "a name under /dev or /proc (a device or a process's descriptor, which the rename of a "
              "file written whole would replace); give the name of a file"};
    std::error_code ec;
    if (!std::filesystem::is_symlink(path, ec)) return {path, ""};
    const std::filesystem::path link = std::filesystem::read_symlink(path, ec);
    if (ec) return {path, "cannot read the symbolic link: " + ec.message()};
    path = link.is_absolute() ? link : path.parent_path() / link;
  }
  return {path, "its symbolic links loop"};
}

// Why no file should be written at `target`, in words ("" when one may).
std::string targetProblem(const LinkTarget& target) {
  if (!target.problem.empty()) return target.problem;
  // Found now, not by the rename at the end of the work (the temporary's name is shortened to fit).
  if (const size_t length = target.path.filename().string().size(); length > NAME_MAX)
    return "its file name is " + std::to_string(length) + " bytes long; a file name takes at most " +
           std::to_string(NAME_MAX);
  struct stat existing {};
  if (::stat(target.path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode))
    return "not a regular file (a device, pipe or socket); outputs are written whole under a temporary name "
           "and renamed onto their path: give the name of a file";
  return "";
}

}  // namespace

std::string outputFileProblem(const std::filesystem::path& output) {
  return targetProblem(followLinks(output));
}

void writeFileAtomically(const std::filesystem::path& output, std::span<const std::byte> bytes,
                         std::string who) {
  TemporaryFile file(output, std::move(who));
  file.writeAt(0, bytes);
  file.commit();
}

TemporaryFolder::TemporaryFolder(const std::string& prefix)
    : TemporaryFolder(std::filesystem::temp_directory_path(), prefix) {}

TemporaryFolder::TemporaryFolder(const std::filesystem::path& parent, std::string prefix) {
  std::string pattern = (parent / fitFileName(std::move(prefix), "-XXXXXX")).string();
  if (!::mkdtemp(pattern.data()))
    throw Error("cannot create a temporary folder " + pattern + ": " + errnoText());
  path_ = pattern;
  signalSlot_ = publishTemporary(path_.string(), /*folder=*/true);
}

TemporaryFolder::~TemporaryFolder() {
  withdrawTemporary(signalSlot_);
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

TemporaryFile::TemporaryFile(std::filesystem::path output, std::string who)
    : output_(std::move(output)), who_(std::move(who)) {
  const LinkTarget target = followLinks(output_);
  if (const std::string problem = targetProblem(target); !problem.empty())
    throw Error(who_ + ": '" + output_.string() + "': " + problem);
  target_ = target.path;
  const std::string pattern =
      (target_.parent_path() / fitFileName(target_.filename().string(), ".tmp-XXXXXX")).string();
  std::vector<char> temporary(pattern.begin(), pattern.end());
  temporary.push_back('\0');
  fd_ = mkstemp(temporary.data());
  if (fd_ < 0)
    throw Error(who_ + ": cannot create output '" + output_.string() + "' (temporary '" + pattern +
                "'): " + errnoText());
  temporary_ = temporary.data();
  signalSlot_ = publishTemporary(temporary_.string());
  fchmod(fd_, 0644);  // mkstemp creates 0600; outputs are ordinary data files
}

TemporaryFile::~TemporaryFile() {
  withdrawTemporary(signalSlot_);
  if (fd_ >= 0) ::close(fd_);
  if (!committed_ && !temporary_.empty()) ::unlink(temporary_.c_str());
}

void removeTemporaryFilesOnSignals() {
  for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGABRT})
    std::signal(signal, removeTemporariesAndDie);
  // Past the file size limit (ulimit -f) a write then fails with EFBIG, which the writers report and clean
  // up after like a full disk, instead of the process dying with its temporary left behind.
  std::signal(SIGXFSZ, SIG_IGN);
}

void forwardSignalsToChild(pid_t child) {
  for (auto& slot : childSlots) {
    pid_t expected = 0;
    if (slot.compare_exchange_strong(expected, child)) return;
  }
  throw Error("more than " + std::to_string(kChildSlots) + " child processes at once");
}

void stopForwardingSignalsToChild(pid_t child) {
  for (auto& slot : childSlots) {
    pid_t expected = child;
    if (slot.compare_exchange_strong(expected, 0)) return;
  }
}

void TemporaryFile::writeAt(uint64_t offset, std::span<const std::byte> bytes) {
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw Error(who_ + ": writing '" + temporary_.string() + "' (for '" + output_.string() +
                  "') failed: " + (n < 0 ? errnoText() : "no progress"));
    done += size_t(n);
  }
}

void TemporaryFile::commit() {
  if (committed_ || fd_ < 0) throw Error(who_ + ": '" + output_.string() + "' committed twice");
  // No fsync: the rename makes a complete file appear atomically to readers, which is what we promise;
  // durability across power loss is the file system's business (zstd's CLI does not sync either).
  withdrawTemporary(signalSlot_);  // from here on the name may be the output's
  signalSlot_ = -1;
  const int fd = fd_;
  fd_ = -1;
  if (::close(fd) != 0) throw Error(who_ + ": closing '" + temporary_.string() + "' failed: " + errnoText());
  if (::rename(temporary_.c_str(), target_.c_str()) != 0)
    throw Error(who_ + ": renaming '" + temporary_.string() + "' to '" + output_.string() +
                "' failed: " + errnoText());
  committed_ = true;
}

}  // namespace ropecast
