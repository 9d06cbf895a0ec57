// The volumes of a file of several the viewer shows (`ropecast view` of a time series, or of a file of
// several channels): each, by its index, made into a brick source (a temporary store,
// tools/temporary_store.h) the first time it is asked for, on a thread of the class's own, one at a time, and
// kept while the kept ones' bytes (their temporary stores, on disk) stay within a budget, the least recently
// shown dropped first: stepping back and forth through a series converts each volume once where they fit.
// Asking for another while one is converted queues it in place of any asked for before that has not started:
// a slider dragged across a series converts the volume in flight and the last one asked for, not every one it
// passed.
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

class SeriesStores {
 public:
  // A volume's source and the bytes it keeps (its temporary store's).
  struct Made {
    std::unique_ptr<BrickSource> source;
    uint64_t bytes = 0;
  };
  // Makes volume `volume`'s source; reports the fraction done through `progress`, which throws once the class
  // stops (the conversion then ends, leaving nothing behind). Throws ropecast::Error when it cannot.
  using Convert = std::function<Made(uint32_t volume, const std::function<void(double)>& progress)>;

  // `count` volumes, of which `shown` is made already; `keepBytes`: the budget of the kept ones.
  SeriesStores(uint32_t count, uint32_t shown, Made shownSource, uint64_t keepBytes, Convert convert,
               std::function<void()> ready);
  // Stops a conversion in flight and waits for its thread.
  ~SeriesStores();
  SeriesStores(const SeriesStores&) = delete;
  SeriesStores& operator=(const SeriesStores&) = delete;

  uint32_t count() const { return count_; }

  // Volume v is made next, unless it is made or being made.
  void ask(uint32_t v);
  // Volume v's source once made, else nullptr. It is kept until shown() names another and then drops it
  // to keep within the budget.
  BrickSource* find(uint32_t v) const;
  // Volume v (made) is shown now, and nothing uses another's source: the least recently shown others are
  // dropped while the kept ones' bytes pass the budget.
  void shown(uint32_t v);
  // How many volumes are kept, and their bytes.
  size_t keptCount() const;
  uint64_t keptBytes() const;

  // The conversion in flight, if any: its volume and the fraction done.
  struct Converting {
    uint32_t volume = 0;
    double fraction = 0.0;
  };
  std::optional<Converting> converting() const;

  // A conversion that failed since the last call: its volume and why; each failure is told once.
  struct Failure {
    uint32_t volume = 0;
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
  struct Kept {
    Made made;
    uint64_t lastShown = 0;  // the value of shows_ when it was last shown, 0: never
  };
  const uint64_t keepBytes_;
  std::map<uint32_t, Kept> made_;
  uint64_t shows_ = 0;
  std::optional<uint32_t> queued_;  // the next to make
  std::optional<Converting> inFlight_;
  std::optional<Failure> failure_;
  bool stopping_ = false;
  std::thread thread_;  // last: started once the members above exist
};

}  // namespace ropecast::tools
