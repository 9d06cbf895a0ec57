// Voxel values read on a thread of its own (the viewer's probe): the window asks for the voxel under the
// pointer every frame and must not wait for a brick's read, which a slow or remote disk makes long. An answer
// that needs no read (the voxel lies in the brick last read) is given at once; any other is read on the
// thread, a newer question replacing one not yet begun, and `answered` is called there when it is known.
//
// Threads: ask() and wait() from one thread at a time (the viewer's main thread); `answered` runs on the
// reader's thread. The BrickSource may be shared with other readers (its reads are thread-safe).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include <glm/vec3.hpp>

#include "store/extract.h"

namespace ropecast {

// A voxel's value in data units, or why it could not be read (a damaged brick, a voxel outside the level).
struct VoxelAnswer {
  double value = 0.0;
  std::string error;  // empty: value holds
};

class AsyncVoxelReader {
 public:
  AsyncVoxelReader(const BrickSource& source, std::function<void()> answered = {});
  ~AsyncVoxelReader();  // waits for a read under way
  AsyncVoxelReader(const AsyncVoxelReader&) = delete;
  AsyncVoxelReader& operator=(const AsyncVoxelReader&) = delete;

  // The voxel's value (VoxelReader::value) when it is known without waiting; else nullopt, and it is read.
  std::optional<VoxelAnswer> ask(uint32_t level, glm::u32vec3 voxel);
  // The voxel's value, waiting for its read (a script's probe).
  VoxelAnswer wait(uint32_t level, glm::u32vec3 voxel);

  // Reads done on the reader's thread so far (tests: an answer from the brick kept reads nothing).
  uint64_t reads() const;

 private:
  struct Question {
    uint32_t level;
    glm::u32vec3 voxel;
    bool operator==(const Question&) const = default;
  };
  std::optional<VoxelAnswer> askLocked(const Question& q);
  VoxelAnswer read(const Question& q);  // reader_ used by the caller alone (reading_ or under the lock)
  void serve();

  VoxelReader reader_;
  std::function<void()> answered_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::optional<Question> question_;  // asked, not yet begun
  std::optional<Question> reading_;   // what the thread is reading (reader_ is its meanwhile)
  bool stop_ = false;
  std::optional<std::pair<Question, VoxelAnswer>> answer_;  // the last answer
  uint64_t reads_ = 0;
  std::thread thread_;  // last: starts when the rest is made
};

}  // namespace ropecast
