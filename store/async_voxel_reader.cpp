#include "store/async_voxel_reader.h"

#include <utility>

#include "core/error.h"

namespace ropecast {

AsyncVoxelReader::AsyncVoxelReader(const BrickSource& source, std::function<void()> answered)
    : reader_(source), answered_(std::move(answered)), thread_([this] { serve(); }) {}

AsyncVoxelReader::~AsyncVoxelReader() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

VoxelAnswer AsyncVoxelReader::read(const Question& q) {
  try {
    return {reader_.value(q.level, q.voxel), ""};
  } catch (const Error& e) {
    return {0.0, e.what()};
  }
}

std::optional<VoxelAnswer> AsyncVoxelReader::askLocked(const Question& q) {
  if (answer_ && answer_->first == q) return answer_->second;
  if (!reading_ && reader_.holds(q.level, q.voxel)) {  // the brick kept: no read, no wait
    answer_.emplace(q, read(q));
    return answer_->second;
  }
  if (question_ != q && reading_ != q) {
    question_ = q;
    changed_.notify_all();
  }
  return std::nullopt;
}

std::optional<VoxelAnswer> AsyncVoxelReader::ask(uint32_t level, glm::u32vec3 voxel) {
  std::lock_guard lock(mutex_);
  return askLocked({level, voxel});
}

VoxelAnswer AsyncVoxelReader::wait(uint32_t level, glm::u32vec3 voxel) {
  std::unique_lock lock(mutex_);
  while (true) {
    if (std::optional<VoxelAnswer> answer = askLocked({level, voxel})) return *answer;
    changed_.wait(lock);
  }
}

uint64_t AsyncVoxelReader::reads() const {
  std::lock_guard lock(mutex_);
  return reads_;
}

void AsyncVoxelReader::serve() {
  std::unique_lock lock(mutex_);
  while (true) {
    changed_.wait(lock, [this] { return stop_ || question_; });
    if (stop_) return;
    const Question q = *question_;
    question_.reset();
    reading_ = q;
    lock.unlock();
    VoxelAnswer answer = read(q);
    lock.lock();
    reading_.reset();
    ++reads_;
    answer_.emplace(q, std::move(answer));
    changed_.notify_all();
    if (answered_) {
      lock.unlock();
      answered_();
      lock.lock();
    }
  }
}

}  // namespace ropecast
