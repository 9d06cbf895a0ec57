// SeriesStores (tools/view_series.h): a series' volumes made on the class's thread as they are asked for,
// each once; a later request replacing a queued one; failures told once; a conversion in flight stopped when
// the class goes. The conversions here are procedural brick sources, some held on a gate.
#include "tools/view_series.h"

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "store/procedural_bricks.h"

namespace ropecast::tools {
namespace {

using namespace std::chrono_literals;

// A source said to keep `bytes`.
SeriesStores::Made smallSource(uint64_t bytes = 10) {
  return {openProceduralBricks("procedural:sphere:8", 8), bytes};
}

constexpr uint64_t kRoomForAll = UINT64_MAX;

// What the conversions did, and a gate that holds them until it opens.
struct Log {
  std::mutex mutex;
  std::condition_variable changed;
  std::vector<uint32_t> started;
  int readies = 0;
  bool gateOpen = true;
  bool stopped = false;  // a conversion saw its progress callback throw

  // Waits (at most 10 s) for `done`; false when it timed out.
  template <typename Done>
  bool waitFor(Done done) {
    std::unique_lock lock(mutex);
    return changed.wait_for(lock, 10s, done);
  }
  void open() {
    std::lock_guard lock(mutex);
    gateOpen = true;
    changed.notify_all();
  }
};

SeriesStores::Convert convertLogged(Log& log, uint32_t failing = UINT32_MAX) {
  return [&log, failing](uint32_t t, const std::function<void(double)>& progress) -> SeriesStores::Made {
    {
      std::unique_lock lock(log.mutex);
      log.started.push_back(t);
      log.changed.notify_all();
      log.changed.wait(lock, [&] { return log.gateOpen; });
    }
    progress(0.5);
    if (t == failing) throw std::runtime_error("volume " + std::to_string(t) + " is unreadable");
    return smallSource();
  };
}

std::function<void()> countReadies(Log& log) {
  return [&log] {
    std::lock_guard lock(log.mutex);
    ++log.readies;
    log.changed.notify_all();
  };
}

TEST(SeriesStores, EachVolumeIsMadeOnceWhenAskedFor) {
  Log log;
  auto shown = smallSource();
  BrickSource* const first = shown.source.get();
  SeriesStores stores(4, 2, std::move(shown), kRoomForAll, convertLogged(log), countReadies(log));
  EXPECT_EQ(stores.count(), 4u);
  EXPECT_EQ(stores.find(2), first);
  EXPECT_EQ(stores.find(1), nullptr);
  stores.ask(2);  // made already
  stores.ask(4);  // past the series
  stores.ask(1);
  ASSERT_TRUE(log.waitFor([&] { return log.readies == 1; }));
  ASSERT_NE(stores.find(1), nullptr);
  EXPECT_NE(stores.find(1), first);
  stores.ask(1);
  stores.ask(2);
  std::this_thread::sleep_for(20ms);
  std::lock_guard lock(log.mutex);
  EXPECT_EQ(log.started, std::vector<uint32_t>{1});
  EXPECT_EQ(log.readies, 1);
}

// A slider dragged across the series: the volume in flight and the last asked for are made, not the
// ones between; the one in flight says how far it is.
TEST(SeriesStores, ALaterRequestReplacesAQueuedOne) {
  Log log;
  log.gateOpen = false;
  SeriesStores stores(6, 0, smallSource(), kRoomForAll, convertLogged(log), countReadies(log));
  stores.ask(1);
  ASSERT_TRUE(log.waitFor([&] { return log.started.size() == 1; }));
  const auto converting = stores.converting();
  ASSERT_TRUE(converting);
  EXPECT_EQ(converting->volume, 1u);
  EXPECT_EQ(converting->fraction, 0.0);
  stores.ask(2);
  stores.ask(3);
  stores.ask(4);
  stores.ask(1);  // in flight: not queued again (4 stays queued)
  log.open();
  ASSERT_TRUE(log.waitFor([&] { return log.readies == 2; }));
  EXPECT_NE(stores.find(1), nullptr);
  EXPECT_EQ(stores.find(2), nullptr);
  EXPECT_EQ(stores.find(3), nullptr);
  EXPECT_NE(stores.find(4), nullptr);
  EXPECT_FALSE(stores.converting());
  std::lock_guard lock(log.mutex);
  EXPECT_EQ(log.started, (std::vector<uint32_t>{1, 4}));
}

TEST(SeriesStores, AFailureIsToldOnceAndTheVolumeMayBeAskedForAgain) {
  Log log;
  SeriesStores stores(3, 0, smallSource(), kRoomForAll, convertLogged(log, /*failing=*/2), countReadies(log));
  EXPECT_FALSE(stores.takeFailure());
  stores.ask(2);
  ASSERT_TRUE(log.waitFor([&] { return log.readies == 1; }));
  const auto failure = stores.takeFailure();
  ASSERT_TRUE(failure);
  EXPECT_EQ(failure->volume, 2u);
  EXPECT_EQ(failure->message, "volume 2 is unreadable");
  EXPECT_FALSE(stores.takeFailure());
  EXPECT_EQ(stores.find(2), nullptr);
  stores.ask(2);
  ASSERT_TRUE(log.waitFor([&] { return log.readies == 2; }));
  EXPECT_TRUE(stores.takeFailure());
}

// Stores of 10 bytes in a budget of 25: the third shown drops the least recently shown, and it is converted
// again when asked for; those made but never shown go before the shown ones.
TEST(SeriesStores, TheLeastRecentlyShownAreDroppedToKeepWithinTheBudget) {
  Log log;
  SeriesStores stores(5, 0, smallSource(), 25, convertLogged(log), countReadies(log));
  const auto make = [&](uint32_t t, int readies) {
    stores.ask(t);
    return log.waitFor([&] { return log.readies == readies; });
  };
  ASSERT_TRUE(make(1, 1));
  stores.shown(1);
  EXPECT_EQ(stores.keptCount(), 2u);
  ASSERT_TRUE(make(2, 2));
  EXPECT_EQ(stores.keptCount(), 3u);  // dropped only when one is shown
  stores.shown(2);
  EXPECT_EQ(stores.keptBytes(), 20u);
  EXPECT_EQ(stores.find(0), nullptr);
  EXPECT_NE(stores.find(1), nullptr);
  EXPECT_NE(stores.find(2), nullptr);
  ASSERT_TRUE(make(3, 3));  // made, never shown
  stores.shown(1);
  EXPECT_EQ(stores.find(3), nullptr);
  EXPECT_NE(stores.find(2), nullptr);
  ASSERT_TRUE(make(0, 4));
  std::lock_guard lock(log.mutex);
  EXPECT_EQ(log.started, (std::vector<uint32_t>{1, 2, 3, 0}));
}

// The class going while a conversion runs stops it at its next progress report: the destructor does not wait
// for the whole conversion, and nothing is kept.
TEST(SeriesStores, GoingStopsAConversionInFlight) {
  Log log;
  {
    SeriesStores stores(
        2, 0, smallSource(), kRoomForAll,
        [&log](uint32_t, const std::function<void(double)>& progress) -> SeriesStores::Made {
          {
            std::lock_guard lock(log.mutex);
            log.started.push_back(1);
            log.changed.notify_all();
          }
          try {
            for (;;) {  // a conversion that would never end by itself
              progress(0.25);
              std::this_thread::sleep_for(1ms);
            }
          } catch (...) {
            std::lock_guard lock(log.mutex);
            log.stopped = true;
            throw;
          }
        },
        countReadies(log));
    stores.ask(1);
    ASSERT_TRUE(log.waitFor([&] { return !log.started.empty(); }));
  }
  std::lock_guard lock(log.mutex);
  EXPECT_TRUE(log.stopped);
  EXPECT_EQ(log.readies, 0);
}

}  // namespace
}  // namespace ropecast::tools
