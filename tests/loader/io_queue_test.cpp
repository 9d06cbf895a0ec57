// Asynchronous brick reads: priority order, dropped and re-requested nodes, bounded ready list, errors,
// shutdown with requests in flight.
#include "loader/io_queue.h"

#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "core/elapsed.h"
#include "tests/loader/testutil_fake_brick_source.h"

namespace ropecast {
namespace {

using testing::FakeBrickSource;
using namespace std::chrono_literals;

NodeKey nodeAtDepth2(uint32_t i) {
  return {2, {i % 4, i / 4 % 4, i / 16}};
}

// 64^3, bricks of 16: depth 2 has 4^3 nodes.
FakeBrickSource makeSource64() {
  return FakeBrickSource({64, 64, 64}, 16);
}

template <class Pred>
bool waitUntil(Pred pred, std::chrono::milliseconds timeout = 5000ms) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  while (!pred()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(1ms);
  }
  return true;
}

std::vector<LoadedBrick> takeAll(IoQueue& q, size_t count) {
  std::vector<LoadedBrick> all;
  while (all.size() < count) {
    if (!q.waitForLoaded(5000ms) && q.pendingCount() == 0) break;
    for (LoadedBrick& b : q.takeLoaded()) all.push_back(std::move(b));
  }
  return all;
}

TEST(IoQueue, ReadsInPriorityOrderAndDeliversTheBricks) {
  FakeBrickSource src = makeSource64();
  src.setGate(false);
  IoQueue q(src, 1);
  q.replaceRequests({{nodeAtDepth2(1), 1.0},
                     {nodeAtDepth2(2), 5.0},
                     {nodeAtDepth2(3), 3.0},
                     {nodeAtDepth2(4), 4.0},
                     {nodeAtDepth2(5), 2.0}});
  ASSERT_TRUE(waitUntil([&] { return q.inFlightCount() == 1; }));
  src.setGate(true);
  const std::vector<LoadedBrick> loaded = takeAll(q, 5);
  ASSERT_EQ(loaded.size(), 5u);
  EXPECT_EQ(src.readOrder(), (std::vector<NodeKey>{nodeAtDepth2(2), nodeAtDepth2(4), nodeAtDepth2(3),
                                                   nodeAtDepth2(5), nodeAtDepth2(1)}));
  for (const LoadedBrick& b : loaded) {
    ASSERT_TRUE(b.brick);
    ASSERT_EQ(b.brick->size(), src.brickBytes());
    EXPECT_EQ((*b.brick)[17], std::byte(testing::patternByte(b.key, 17)));
  }
  EXPECT_EQ(q.pendingCount(), 0u);
}

TEST(IoQueue, DropsRequestsNoLongerWantedAndReadsThemWhenWantedAgain) {
  FakeBrickSource src = makeSource64();
  src.setGate(false);
  IoQueue q(src, 1);
  q.replaceRequests({{nodeAtDepth2(0), 10.0}, {nodeAtDepth2(1), 5.0}, {nodeAtDepth2(2), 1.0}});
  ASSERT_TRUE(waitUntil([&] { return q.inFlightCount() == 1; }));  // nodeAtDepth2(0) is being read
  // The next frame wants nodeAtDepth2(2) only: nodeAtDepth2(1) is dropped; nodeAtDepth2(0), in flight, is not
  // read twice.
  q.replaceRequests({{nodeAtDepth2(2), 1.0}, {nodeAtDepth2(0), 10.0}});
  EXPECT_EQ(q.queuedCount(), 1u);
  EXPECT_EQ(q.pendingCount(), 2u);
  src.setGate(true);
  std::vector<LoadedBrick> loaded = takeAll(q, 2);
  ASSERT_EQ(loaded.size(), 2u);
  EXPECT_EQ(src.readOrder(), (std::vector<NodeKey>{nodeAtDepth2(0), nodeAtDepth2(2)}));
  EXPECT_EQ(q.readsStarted(), 2u);

  q.replaceRequests({{nodeAtDepth2(1), 1.0}});
  loaded = takeAll(q, 1);
  ASSERT_EQ(loaded.size(), 1u);
  EXPECT_EQ(loaded[0].key, nodeAtDepth2(1));
  EXPECT_EQ(q.readsStarted(), 3u);
}

TEST(IoQueue, BoundsTheBricksWaitingToBeTaken) {
  FakeBrickSource src = makeSource64();
  IoQueue q(src, 2, /*maxReadyBricks=*/3);
  std::vector<BrickRequest> requests;
  for (uint32_t i = 0; i < 20; ++i) requests.push_back({nodeAtDepth2(i), double(i)});
  q.replaceRequests(requests);
  ASSERT_TRUE(waitUntil([&] { return q.readsStarted() >= 3; }));
  std::this_thread::sleep_for(30ms);
  EXPECT_EQ(q.readsStarted(), 3u);  // no room for more until the render thread takes them
  const std::vector<LoadedBrick> all = takeAll(q, 20);
  EXPECT_EQ(all.size(), 20u);
  EXPECT_EQ(src.reads(), 20u);
}

TEST(IoQueue, ReportsAFailedRead) {
  FakeBrickSource src = makeSource64();
  src.failOn(nodeAtDepth2(3));
  IoQueue q(src, 2);
  q.replaceRequests({{nodeAtDepth2(2), 1.0}, {nodeAtDepth2(3), 2.0}});
  const std::vector<LoadedBrick> all = takeAll(q, 2);
  ASSERT_EQ(all.size(), 2u);
  for (const LoadedBrick& b : all) {
    if (b.key == nodeAtDepth2(3)) {
      EXPECT_FALSE(b.brick);
      EXPECT_NE(b.error.find("injected failure"), std::string::npos);
    } else {
      EXPECT_TRUE(b.brick);
      EXPECT_TRUE(b.error.empty());
    }
  }
}

TEST(IoQueue, ShutsDownWithRequestsInFlightWithoutWaitingForTheQueue) {
  FakeBrickSource fake = makeSource64();
  DelayedBrickSource slow(fake, 40.0);
  const auto start = SteadyClock::now();
  {
    IoQueue q(slow, 2);
    std::vector<BrickRequest> requests;
    for (uint32_t i = 0; i < 64; ++i) requests.push_back({nodeAtDepth2(i), double(i)});
    q.replaceRequests(requests);
    ASSERT_TRUE(waitUntil([&] { return q.inFlightCount() > 0; }));
  }  // destroyed with 2 reads in flight and ~60 queued
  const double ms = millisecondsSince(start);
  EXPECT_LT(ms, 64 * 40.0 / 2 / 4);  // far less than reading the queue
  EXPECT_LE(fake.reads(), 6u);
}

TEST(IoQueue, WaitsUntilEveryReadIsDoneOrTheTimeout) {
  FakeBrickSource fake = makeSource64();
  DelayedBrickSource slow(fake, 20.0);
  IoQueue q(slow, 2);
  std::vector<BrickRequest> requests;
  for (uint32_t i = 0; i < 6; ++i) requests.push_back({nodeAtDepth2(i), double(i)});
  q.replaceRequests(requests);
  EXPECT_FALSE(q.waitUntilIdle(1ms));  // 6 reads of 20 ms on 2 workers take 60 ms
  EXPECT_GT(q.pendingCount(), 0u);
  EXPECT_TRUE(q.waitUntilIdle(5000ms));
  EXPECT_EQ(q.pendingCount(), 0u);
  EXPECT_EQ(q.takeLoaded().size(), 6u);
  EXPECT_TRUE(q.waitUntilIdle(0ms));  // nothing pending: at once
}

TEST(IoQueue, AFullReadyListEndsTheWaitForIdleWorkers) {
  // One worker, room for 2 read bricks, 5 requests: after 2 reads the workers wait for takeLoaded, so the
  // wait ends then, not at the timeout.
  FakeBrickSource fake = makeSource64();
  IoQueue q(fake, 1, 2);
  std::vector<BrickRequest> requests;
  for (uint32_t i = 0; i < 5; ++i) requests.push_back({nodeAtDepth2(i), double(i)});
  q.replaceRequests(requests);
  EXPECT_TRUE(q.waitUntilIdle(5000ms));  // idle, not timed out
  EXPECT_EQ(q.queuedCount(), 3u);
  EXPECT_EQ(q.takeLoaded().size(), 2u);
}

TEST(IoQueue, DelayedSourceAddsLatencyToEveryRead) {
  FakeBrickSource fake = makeSource64();
  DelayedBrickSource slow(fake, 25.0);
  BrickBytes out(slow.brickBytes());
  const auto start = SteadyClock::now();
  slow.readBrick(nodeAtDepth2(1), out);
  slow.readBrick(nodeAtDepth2(2), out);
  const double ms = millisecondsSince(start);
  EXPECT_GE(ms, 50.0);
  EXPECT_EQ(out[5], std::byte(testing::patternByte(nodeAtDepth2(2), 5)));
  EXPECT_EQ(slow.node(nodeAtDepth2(1)).kind, NodeKind::Data);
}

}  // namespace
}  // namespace ropecast
