// Temporary files for outputs: a file written under a temporary name next to its output and renamed when
// complete, a folder of files a command drops at its end, and the signal handlers that remove both when a
// command is interrupted, so that no command leaves a half-written output or its scratch behind.
//
// Threads: as each class says; removeTemporaryFilesOnSignals from the main thread once.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>

#include <sys/types.h>

namespace ropecast {

// Why `output` cannot be written through a TemporaryFile, in words ("" when it can): it exists and is not a
// regular file (a device, pipe or socket would be replaced by the rename, and cannot take writes at offsets),
// or it is, or links to, a name under /dev or /proc (/dev/stdout: a descriptor of the process, which a rename
// would replace by a file), or its symbolic links loop.
std::string outputFileProblem(const std::filesystem::path& output);

// A file being written under a temporary name next to `output` ("OUT.tmp-XXXXXX", OUT shortened where the
// name would be too long for a file name); commit() renames it onto `output`, destruction without commit
// removes it. An output that is a symbolic link is written where the link leads, so that the link stays.
// writeAt() may be called from several threads at once.
class TemporaryFile {
 public:
  // `who` names the caller in errors ("StoreWriter", "extract"). Throws ropecast::Error naming `output`,
  // also when outputFileProblem(output) finds one.
  TemporaryFile(std::filesystem::path output, std::string who);
  ~TemporaryFile();
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;

  void writeAt(uint64_t offset, std::span<const std::byte> bytes);
  void commit();  // closes and renames onto the output path
  const std::filesystem::path& output() const { return output_; }
  const std::filesystem::path& path() const { return temporary_; }

 private:
  std::filesystem::path output_, temporary_;
  std::filesystem::path target_;  // output_ with its symbolic links followed: what the rename replaces
  std::string who_;
  int fd_ = -1;
  int signalSlot_ = -1;  // where removeTemporaryFilesOnSignals finds the temporary name
  bool committed_ = false;
};

// Writes `bytes` as the whole of `output` through a TemporaryFile: it appears complete, or not at all. Throws
// ropecast::Error naming `who` and `output`.
void writeFileAtomically(const std::filesystem::path& output, std::span<const std::byte> bytes,
                         std::string who);

// A new folder under the system's temporary directory ("PREFIX-XXXXXX") for files a command writes and then
// drops: removed with everything in it at destruction, and (its own files, not subfolders) on SIGINT/SIGTERM
// with removeTemporaryFilesOnSignals. Throws ropecast::Error when it cannot be made. Owned by one thread.
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix);
  // The same in `parent` ("PARENT/PREFIX-XXXXXX", the prefix shortened to fit a file name): files staged
  // there can be renamed into `parent`.
  TemporaryFolder(const std::filesystem::path& parent, std::string prefix);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;

  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
  int signalSlot_ = -1;
};

// For the command-line tools: installs SIGINT/SIGTERM/SIGHUP/SIGQUIT/SIGPIPE/SIGABRT handlers that remove
// every TemporaryFile still open in the process (async-signal-safe: unlink only) and then die of the signal
// as before, so an interrupted convert, extract or render, or one a library aborts (GDCM asserts on some
// damaged DICOM files), leaves nothing behind either; ignores SIGXFSZ, so that a write past the file size
// limit fails (EFBIG) as on a full disk. Main thread, once.
void removeTemporaryFilesOnSignals();

// A child process (posix_spawn) that the handlers of removeTemporaryFilesOnSignals pass their signal on to,
// and wait for, before they remove the temporaries: a command interrupted on its own (`kill PID`, not a
// terminal's Ctrl-C to the whole process group) leaves no child running, nor a child's file in its temporary
// folder. At most 64 at once (more throw ropecast::Error). Main thread; stop once the child has been waited
// for, before its pid can be reused.
void forwardSignalsToChild(pid_t child);
void stopForwardingSignalsToChild(pid_t child);

}  // namespace ropecast
