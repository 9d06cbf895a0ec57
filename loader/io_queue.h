// IoQueue: brick reads (I/O and decompression, inside BrickSource::readBrick) on worker threads, fed by a
// priority-ordered request queue. The render thread replaces the whole wanted set each frame; queued requests
// not in the new set are dropped, so the workers only ever read what the latest frame asked for. Read bricks
// wait in a ready list until the render thread takes them (into the CPU cache).
//
// Also DelayedBrickSource, a decorator adding latency to every read (`--io-delay-ms`), to show asynchrony.
//
// Threads: an IoQueue is owned by one thread (the render thread), which alone calls its methods; the workers
// are internal. The BrickSource must outlive the IoQueue and be safe to read from several threads
// (brick_source.h). The destructor drops queued requests and joins the workers after their current read (no
// hang, no leak).
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <string_view>
#include <thread>
#include <unordered_set>
#include <vector>

#include "loader/brick_cache.h"
#include "store/brick_source.h"

namespace ropecast {

// The I/O threads a loader starts unless told (`--io-threads`): one per core, at least 2 (one reads while the
// other decompresses) and at most 8. With a GPU the cores have nothing else to do while a view loads; with a
// software rasterizer they draw the frames too.
inline constexpr std::string_view kDefaultIoThreadsRule = "one per core, at least 2, at most 8";
inline constexpr uint32_t kMaxIoThreads = 256;
uint32_t defaultIoThreads();

struct BrickRequest {
  NodeKey key;
  double priority = 0.0;  // larger first
};

struct LoadedBrick {
  NodeKey key;
  SharedBrick brick;       // null when the read failed
  std::string error;       // the ropecast::Error message of a failed read
  uint64_t bytesRead = 0;  // BrickSource::compressedBytes of a successful read, else 0
};

class IoQueue {
 public:
  // maxReadyBricks bounds the bricks read but not yet taken, so memory stays bounded when frames are slow.
  IoQueue(const BrickSource& source, uint32_t workerCount, size_t maxReadyBricks = 64);
  ~IoQueue();
  IoQueue(const IoQueue&) = delete;
  IoQueue& operator=(const IoQueue&) = delete;

  // The wanted set of this frame. Keys already being read or read and not yet taken are not queued again.
  void replaceRequests(std::vector<BrickRequest> requests);
  // Bricks read since the last call (in completion order).
  std::vector<LoadedBrick> takeLoaded();
  // Blocks until a read brick is waiting, or nothing is queued or being read, or the timeout passes.
  // Returns whether a read brick is waiting.
  bool waitForLoaded(std::chrono::milliseconds timeout);
  // Blocks until the workers are idle: nothing is being read, and nothing is queued or the ready list is full
  // (they wait for takeLoaded), or the timeout passes. Returns whether they are idle.
  bool waitUntilIdle(std::chrono::milliseconds timeout);

  size_t queuedCount() const;
  size_t inFlightCount() const;
  // Queued + being read: what the loader still waits for.
  size_t pendingCount() const;
  // Reads started since construction (tests: dropped requests are never read).
  uint64_t readsStarted() const;

 private:
  void workerLoop();
  void stopWorkers();  // stops and joins the workers started so far

  const BrickSource& source_;
  mutable std::mutex mutex_;
  std::condition_variable workAvailable_;  // workers wait: queue non-empty (and room in ready) or stopping
  std::condition_variable progress_;       // render thread waits: a brick is ready or nothing is pending
  std::vector<BrickRequest> queue_;        // sorted by increasing priority: workers take from the back
  std::unordered_set<NodeKey, NodeKeyHash> inFlight_;
  std::unordered_set<NodeKey, NodeKeyHash> readyKeys_;
  std::vector<LoadedBrick> ready_;
  size_t maxReadyBricks_;
  uint64_t readsStarted_ = 0;
  bool stopping_ = false;
  std::vector<std::thread> workers_;
};

// Adds `delayMs` of latency before every readBrick of `inner` (which must outlive it). Any thread.
class DelayedBrickSource final : public BrickSource {
 public:
  DelayedBrickSource(const BrickSource& inner, double delayMs) : inner_(inner), delayMs_(delayMs) {}
  const BrickSourceInfo& info() const override { return inner_.info(); }
  NodeInfo node(const NodeKey& key) const override { return inner_.node(key); }
  void readBrick(const NodeKey& key, std::span<std::byte> out) const override;
  uint64_t compressedBytes(const NodeKey& key) const override { return inner_.compressedBytes(key); }

 private:
  const BrickSource& inner_;
  double delayMs_;
};

}  // namespace ropecast
