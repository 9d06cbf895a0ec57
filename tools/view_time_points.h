// The time points of a series the viewer shows (`ropecast view` of a file of several time points): each made
// into a brick source (a temporary store, tools/temporary_store.h) the first time it is asked for, on a
// thread of the class's own, one at a time, and kept for the session, so that stepping back and forth
// through a series converts each time point once. Asking for another while one is converted queues it in
// place of any asked for before that has not started: a slider dragged across a series converts the time
// point in flight and the last one asked for, not every one it passed.
//
// Threads: every member from one thread (the viewer's main thread). `convert` runs on the class's thread, and
// `ready` is called there when a conversion ends (the viewer wakes its window with it).
#pragma once

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "store/brick_source.h"

namespace ropecast::tools {

class TimePointStores {
 public:
  // Makes time point t's source; reports the fraction done through `progress`, which throws once the class
  // stops (the conversion then ends, leaving nothing behind). Throws ropecast::Error when it cannot.
  using Convert =
      std::function<std::unique_ptr<BrickSource>(uint32_t t, const std::function<void(double)>& progress)>;

  // `count` time points, of which `shown` is already made (`shownSource`).
  TimePointStores(uint32_t count, uint32_t shown, std::unique_ptr<BrickSource> shownSource, Convert convert,
                  std::function<void()> ready);
  // Stops a conversion in flight and waits for its thread.
  ~TimePointStores();
  TimePointStores(const TimePointStores&) = delete;
  TimePointStores& operator=(const TimePointStores&) = delete;

  uint32_t count() const { return count_; }

  // Time point t is made next, unless it is made or being made.
  void ask(uint32_t t);
  // Time point t's source once made (it lives as long as the class), else nullptr.
  BrickSource* find(uint32_t t) const;

  // The conversion in flight, if any: its time point and the fraction done.
  struct Converting {
    uint32_t timePoint = 0;
    double fraction = 0.0;
  };
  std::optional<Converting> converting() const;

  // A conversion that failed since the last call: its time point and why; each failure is told once.
  struct Failure {
    uint32_t timePoint = 0;
    std::string message;
  };
  std::optional<Failure> takeFailure();

 private:
  void work();

  const uint32_t count_;
  const Convert convert_;
  const std::function<void()> ready_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::map<uint32_t, std::unique_ptr<BrickSource>> made_;
  std::optional<uint32_t> queued_;  // the next to make
  std::optional<Converting> inFlight_;
  std::optional<Failure> failure_;
  bool stopping_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace ropecast::tools
