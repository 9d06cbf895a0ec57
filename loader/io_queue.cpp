#include "loader/io_queue.h"

#include <algorithm>
#include <exception>

#include "core/error.h"

namespace ropecast {

uint32_t defaultIoThreads() {
  const unsigned cores = std::thread::hardware_concurrency();  // 0 when unknown
  return std::clamp<uint32_t>(cores, 2, 8);
}

IoQueue::IoQueue(const BrickSource& source, uint32_t workerCount, size_t maxReadyBricks)
    : source_(source), maxReadyBricks_(std::max<size_t>(maxReadyBricks, 1)) {
  if (workerCount == 0) throw Error("IoQueue: at least one I/O thread is needed");
  workers_.reserve(workerCount);
  try {
    for (uint32_t i = 0; i < workerCount; ++i) workers_.emplace_back([this] { workerLoop(); });
  } catch (...) {  // a thread that cannot start: the started ones end before the members they use go
    stopWorkers();
    throw;
  }
}

IoQueue::~IoQueue() {
  stopWorkers();
}

void IoQueue::stopWorkers() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
    queue_.clear();
  }
  workAvailable_.notify_all();
  progress_.notify_all();
  for (std::thread& w : workers_) w.join();
}

void IoQueue::replaceRequests(std::vector<BrickRequest> requests) {
  {
    std::lock_guard lock(mutex_);
    std::erase_if(requests,
                  [&](const BrickRequest& r) { return inFlight_.count(r.key) || readyKeys_.count(r.key); });
    // Stable, so equal priorities keep the caller's order (taken from the back: the caller's first comes
    // first).
    std::reverse(requests.begin(), requests.end());
    std::stable_sort(requests.begin(), requests.end(),
                     [](const BrickRequest& a, const BrickRequest& b) { return a.priority < b.priority; });
    // Duplicated keys: keep the highest priority (the last one after sorting).
    std::unordered_set<NodeKey, NodeKeyHash> seen;
    std::vector<BrickRequest> unique;
    unique.reserve(requests.size());
    for (auto it = requests.rbegin(); it != requests.rend(); ++it) {
      if (seen.insert(it->key).second) unique.push_back(*it);
    }
    std::reverse(unique.begin(), unique.end());
    queue_ = std::move(unique);
  }
  workAvailable_.notify_all();
  progress_.notify_all();
}

std::vector<LoadedBrick> IoQueue::takeLoaded() {
  std::vector<LoadedBrick> out;
  {
    std::lock_guard lock(mutex_);
    out.swap(ready_);
    readyKeys_.clear();
  }
  workAvailable_.notify_all();  // room in the ready list again
  return out;
}

bool IoQueue::waitForLoaded(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  progress_.wait_for(lock, timeout, [&] { return !ready_.empty() || (queue_.empty() && inFlight_.empty()); });
  return !ready_.empty();
}

bool IoQueue::waitUntilIdle(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  // A full ready list stops the workers until the caller takes it: waiting longer would change nothing.
  return progress_.wait_for(lock, timeout, [&] {
    return inFlight_.empty() && (queue_.empty() || ready_.size() >= maxReadyBricks_);
  });
}

size_t IoQueue::queuedCount() const {
  std::lock_guard lock(mutex_);
  return queue_.size();
}

size_t IoQueue::inFlightCount() const {
  std::lock_guard lock(mutex_);
  return inFlight_.size();
}

size_t IoQueue::pendingCount() const {
  std::lock_guard lock(mutex_);
  return queue_.size() + inFlight_.size();
}

uint64_t IoQueue::readsStarted() const {
  std::lock_guard lock(mutex_);
  return readsStarted_;
}

void IoQueue::workerLoop() {
  const size_t brickBytes = source_.brickBytes();
  std::unique_lock lock(mutex_);
  for (;;) {
    // Bricks in flight count against the ready bound too: each will land in the ready list.
    workAvailable_.wait(lock, [&] {
      return stopping_ || (!queue_.empty() && ready_.size() + inFlight_.size() < maxReadyBricks_);
    });
    if (stopping_) return;
    const BrickRequest request = queue_.back();
    queue_.pop_back();
    inFlight_.insert(request.key);
    ++readsStarted_;
    lock.unlock();

    LoadedBrick loaded{request.key, nullptr, {}, 0};
    try {
      auto brick = std::make_shared<BrickBytes>(brickBytes);
      source_.readBrick(request.key, *brick);
      loaded.brick = std::move(brick);
      loaded.bytesRead = source_.compressedBytes(request.key);
    } catch (const std::exception& e) {
      loaded.error = e.what();
    } catch (...) {  // nothing may leave a worker thread: the render thread hears of it as a failed read
      loaded.error = "reading brick failed with an unknown exception";
    }

    lock.lock();
    inFlight_.erase(request.key);
    if (!stopping_) {
      readyKeys_.insert(request.key);
      ready_.push_back(std::move(loaded));
    }
    progress_.notify_all();
  }
}

void DelayedBrickSource::readBrick(const NodeKey& key, std::span<std::byte> out) const {
  if (delayMs_ > 0.0) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>(delayMs_));
  inner_.readBrick(key, out);
}

}  // namespace ropecast
