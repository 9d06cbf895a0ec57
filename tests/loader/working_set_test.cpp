// The per-frame loader end to end on a fake source: convergence from a cold cache to the synchronous cut,
// budgets never exceeded, never a hole, no I/O for emptiness changes or revisited views, which bricks a full
// GPU pool gives up (used ones last, hidden ones first), shutdown in flight, a synchronous load's progress.
#include "loader/working_set.h"

#include <algorithm>
#include <chrono>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include <gtest/gtest.h>

#include "core/elapsed.h"
#include "core/error.h"
#include "tests/loader/testutil_fake_brick_source.h"

namespace ropecast {
namespace {

using testing::FakeBrickSource;
using testing::isFullTiling;
using testing::KeyLess;

// 128^3 with bricks of 16: depths 0..3. Depth-3 nodes with z = 7 hold only low values (empty for iso 100),
// depth-2 node (3,3,3) is constant 150.
NodeInfo sceneNode(const NodeKey& k) {
  if (k.depth >= 2 && (k.coord >> (k.depth - 2)) == glm::u32vec3(3, 3, 3))
    return {NodeKind::Constant, 150, 150};
  if (k.depth == 3 && k.coord.z == 7) return {NodeKind::Data, 0, 20};
  return {NodeKind::Data, 0, 255};
}
FakeBrickSource makeScene() {
  return FakeBrickSource({128, 128, 128}, 16, sceneNode);
}

FrameInput frameFrom(glm::dvec3 eye, uint32_t heightPx = 600, glm::dvec3 target = {64, 64, 64}) {
  FrameInput in;
  in.view.camera.eye = eye;
  in.view.camera.target = target;
  in.view.camera.up = {0, 0, 1};
  in.view.camera.fovYDeg = 40.0;
  in.view.viewportWidth = heightPx;
  in.view.viewportHeight = heightPx;
  return in;
}

// The renderer's side: applies uploads to a simulated pool and checks every frame's plan.
struct FakePool {
  std::map<uint32_t, NodeKey> slotKey;

  void check(const WorkingSetFrame& f, const FakeBrickSource& src, const WorkingSetConfig& cfg) {
    EXPECT_LE(f.stats.bytesUploaded, cfg.uploadBudgetBytes);
    EXPECT_EQ(f.stats.bytesUploaded, f.uploads.size() * src.brickBytes());
    EXPECT_LE(f.stats.cpuCacheBytes, cfg.cpuCacheBytes);
    EXPECT_LE(f.stats.bricksResident, cfg.gpuSlots);
    std::set<uint32_t> uploadedSlots;
    for (const BrickUpload& u : f.uploads) {
      EXPECT_LT(u.slot, cfg.gpuSlots);
      EXPECT_TRUE(uploadedSlots.insert(u.slot).second) << "two uploads to slot " << u.slot;
      ASSERT_TRUE(u.brick);
      ASSERT_EQ(u.brick->size(), src.brickBytes());
      const NodeInfo info = src.node(u.key);
      const uint8_t expected =
          info.kind == NodeKind::Constant ? uint8_t(info.minValue) : testing::patternByte(u.key, 1234);
      EXPECT_EQ((*u.brick)[1234], std::byte(expected));
      slotKey[u.slot] = u.key;
    }
    EXPECT_TRUE(isFullTiling(f.leaves, src.info().layout.maxDepth));
    std::set<uint32_t> cutSlots;
    for (const PlannedLeaf& l : f.leaves) {
      if (l.content != LeafContent::Brick) continue;
      EXPECT_TRUE(cutSlots.insert(l.slot).second) << "slot " << l.slot << " twice in the cut";
      ASSERT_TRUE(slotKey.count(l.slot)) << "leaf in a slot never uploaded";
      EXPECT_EQ(slotKey[l.slot], l.key) << "leaf's slot holds another brick";
    }
  }
};

void debugPrint(const WorkingSetFrame& f) {
  if (!getenv("DBG")) return;
  std::map<LeafReason, int> m;
  for (auto& l : f.leaves) ++m[l.reason];
  for (auto [r, c] : m) fprintf(stderr, " %s=%d", leafReasonName(r), c);
  fprintf(stderr, "\n");
}

std::map<NodeKey, LeafContent, KeyLess> cutOf(const WorkingSetFrame& f) {
  std::map<NodeKey, LeafContent, KeyLess> m;
  for (const PlannedLeaf& l : f.leaves) m[l.key] = l.content;
  return m;
}

WorkingSetConfig config(uint32_t slots = 400) {
  WorkingSetConfig c;
  c.gpuSlots = slots;
  c.cpuCacheBytes = 200 * 46656;  // 200 bricks of 36^3 bytes
  c.ioThreads = 2;
  return c;
}

const auto isoEmpty = [](uint16_t lo, uint16_t hi) { return !(lo <= 100 && 100 <= hi); };

TEST(WorkingSet, ColdAsyncFramesConvergeToTheSynchronousCutWithinBudgets) {
  const glm::dvec3 eye(64 + 150, 64 - 90, 64 + 60);
  FrameInput in = frameFrom(eye);
  in.isEmpty = isoEmpty;

  FakeBrickSource syncSrc = makeScene();
  WorkingSet sync(syncSrc, config());
  const WorkingSetFrame reference = sync.updateUntilConverged(in);
  ASSERT_TRUE(reference.converged);
  FakePool syncPool;
  syncPool.check(reference, syncSrc, config());
  const auto referenceCut = cutOf(reference);
  ASSERT_GT(referenceCut.size(), 100u);

  FakeBrickSource fake = makeScene();
  DelayedBrickSource slow(fake, 2.0);
  WorkingSetConfig cfg = config();
  cfg.uploadBudgetBytes = 6 * fake.brickBytes();
  WorkingSet ws(slow, cfg);
  FakePool pool;
  bool converged = false;
  int frames = 0;
  for (; frames < 2000 && !converged; ++frames) {
    const WorkingSetFrame f = ws.update(in);
    pool.check(f, fake, cfg);
    if (frames == 0) {
      ASSERT_EQ(f.leaves.size(), 1u);  // cold: the root is not read yet, and update() did not wait for it
      EXPECT_EQ(f.leaves[0].content, LeafContent::Missing);
      EXPECT_GE(f.stats.requestsPending, 1u);
      EXPECT_FALSE(f.converged);
    }
    converged = f.converged;
    debugPrint(f);
    if (converged) {
      EXPECT_EQ(cutOf(f), referenceCut);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(converged);
  EXPECT_GT(frames, 5);  // the upload budget spread the work over frames
  // Constant and empty nodes were never read.
  for (const NodeKey& k : fake.readOrder()) {
    EXPECT_NE(fake.node(k).kind, NodeKind::Constant);
  }
}

TEST(WorkingSet, TheSynchronousLoadReportsItsProgressUntilNothingIsPending) {
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  in.isEmpty = isoEmpty;
  FakeBrickSource src = makeScene();
  WorkingSet ws(src, config());
  std::vector<LoadProgress> reports;
  const WorkingSetFrame f = ws.updateUntilConverged(in, [&](const LoadProgress& p) { reports.push_back(p); });
  ASSERT_TRUE(f.converged);
  // A report while reads are pending and one when none are (how many between depends on how the reads and
  // the waves of refinement interleave on this machine).
  ASSERT_GE(reports.size(), 2u);
  for (size_t i = 1; i < reports.size(); ++i) {
    EXPECT_GE(reports[i].bricksRead, reports[i - 1].bricksRead);
    EXPECT_GE(reports[i].bytesRead, reports[i - 1].bytesRead);
  }
  // The first pass asked for reads, which later reports count as read. (At its own report they may be queued,
  // in flight, or already done and not yet taken into the cache: pending or not, by timing.)
  EXPECT_LT(reports.front().bricksRead, reports.back().bricksRead);
  EXPECT_EQ(reports.back().readsPending, 0u);
  EXPECT_EQ(reports.back().bricksRead, src.reads());
  EXPECT_EQ(reports.back().bytesRead, f.stats.bytesRead);
}

TEST(WorkingSet, EmptinessChangesAndRevisitedViewsNeedNoIo) {
  FakeBrickSource src = makeScene();
  WorkingSetConfig cfg = config(600);
  cfg.cpuCacheBytes = 600 * src.brickBytes();
  WorkingSet ws(src, cfg);
  FrameInput a = frameFrom({64 + 150, 64 - 90, 64 + 60});
  const WorkingSetFrame all = ws.updateUntilConverged(a);  // nothing empty but the source's own
  ASSERT_TRUE(all.converged);
  const uint64_t reads = src.reads();
  EXPECT_EQ(all.stats.bytesRead, reads * src.brickBytes());  // a generated source counts whole bricks

  a.isEmpty = isoEmpty;  // a narrower selection: every node it keeps was already read
  const WorkingSetFrame iso = ws.updateUntilConverged(a);
  EXPECT_TRUE(iso.converged);
  EXPECT_EQ(src.reads(), reads);
  EXPECT_EQ(iso.stats.bytesRead, 0u);
  EXPECT_NE(cutOf(iso), cutOf(all));
  EXPECT_TRUE(iso.uploads.empty());  // all on the GPU already

  FrameInput b = frameFrom({64 - 120, 64 + 150, 64 - 40});
  b.isEmpty = isoEmpty;
  ws.updateUntilConverged(b);
  const uint64_t readsAfterB = src.reads();
  EXPECT_GT(readsAfterB, reads);
  const WorkingSetFrame back = ws.updateUntilConverged(a);  // back to the first view: from the caches
  EXPECT_TRUE(back.converged);
  EXPECT_EQ(src.reads(), readsAfterB);
  EXPECT_EQ(cutOf(back), cutOf(iso));
  EXPECT_EQ(back.stats.cacheMisses, 0u);
}

TEST(WorkingSet, SmallPoolAndSmallCpuCacheStayWithinBudget) {
  FakeBrickSource fake = makeScene();
  WorkingSetConfig cfg = config(/*slots=*/40);
  cfg.cpuCacheBytes = 16 * fake.brickBytes();
  cfg.uploadBudgetBytes = 5 * fake.brickBytes();
  WorkingSet ws(fake, cfg);
  FakePool pool;
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  in.isEmpty = isoEmpty;
  bool converged = false;
  for (int i = 0; i < 2000 && !converged; ++i) {
    const WorkingSetFrame f = ws.update(in);
    pool.check(f, fake, cfg);
    debugPrint(f);
    EXPECT_LE(ws.cache().bytes(), cfg.cpuCacheBytes);
    converged = f.converged;
    if (converged) {
      size_t poolFull = 0;
      for (const PlannedLeaf& l : f.leaves) poolFull += l.reason == LeafReason::PoolFull;
      EXPECT_GT(poolFull, 0u);
      EXPECT_EQ(f.stats.leavesPoolFull, poolFull);  // what `render` warns about
    }
    if (!converged)
      ws.io().pendingCount() ? (void)std::this_thread::sleep_for(std::chrono::milliseconds(1)) : void();
  }
  EXPECT_TRUE(converged);
  // The same budgets synchronously give the same cut: the pool limit does not depend on load timing.
  FakeBrickSource fake2 = makeScene();
  WorkingSet sync(fake2, cfg);
  const WorkingSetFrame ref = sync.updateUntilConverged(in);
  const WorkingSetFrame last = ws.update(in);
  EXPECT_EQ(cutOf(ref), cutOf(last));
}

TEST(WorkingSet, APerFrameUploadLimitIsNeverExceededAndStillConverges) {
  // The renderer's time budget arrives as FrameInput::uploadBudgetBytes, changing every frame; the smaller of
  // it and the configured budget applies, and never less than one brick (else nothing could ever refine).
  FakeBrickSource fake = makeScene();
  WorkingSetConfig cfg = config();
  cfg.uploadBudgetBytes = 6 * fake.brickBytes();
  WorkingSet ws(fake, cfg);
  FakePool pool;
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  in.isEmpty = isoEmpty;
  const uint64_t limitsInBricks[] = {0, 1, 3, 8, 2, 100};
  bool converged = false;
  uint64_t framesAtLimit = 0;
  for (int i = 0; i < 3000 && !converged; ++i) {
    const uint64_t limit = limitsInBricks[i % 6] * fake.brickBytes();
    in.uploadBudgetBytes = limit;
    const WorkingSetFrame f = ws.update(in);
    pool.check(f, fake, cfg);
    const uint64_t allowed = std::max(std::min(limit, cfg.uploadBudgetBytes), fake.brickBytes());
    EXPECT_LE(f.stats.bytesUploaded, allowed) << "frame " << i;
    framesAtLimit += f.stats.bytesUploaded == allowed;
    converged = f.converged;
    if (!converged && ws.io().pendingCount()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_TRUE(converged);
  EXPECT_GT(framesAtLimit, 3u);  // the limits did bind
  FakeBrickSource fake2 = makeScene();
  WorkingSet sync(fake2, cfg);
  in.uploadBudgetBytes = std::numeric_limits<uint64_t>::max();
  EXPECT_EQ(cutOf(sync.updateUntilConverged(in)), cutOf(ws.update(in)));
}

// The nodes holding a brick in a WorkingSet's GPU pool.
TEST(WorkingSet, TheSmallestCpuCacheWithAOneBrickUploadBudgetConverges) {
  // 16 bricks of CPU cache, reads landing up to half of it, one upload a frame: a node's children must stay
  // in the cache for the frames they wait for their siblings and their uploads, or they are read again and
  // again and the cut never grows.
  FakeBrickSource fake = makeScene();
  WorkingSetConfig cfg = config();
  cfg.cpuCacheBytes = kMinCpuCacheBricks * fake.brickBytes();
  cfg.uploadBudgetBytes = fake.brickBytes();
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  in.isEmpty = isoEmpty;
  // Synchronously the budget does not apply (one frame): a pass per level or wave, not one per brick.
  WorkingSet sync(fake, cfg);
  const WorkingSetFrame reference = sync.updateUntilConverged(in, {}, /*maxFrames=*/64);
  ASSERT_TRUE(reference.converged);
  const uint64_t bricks = reference.uploads.size();
  ASSERT_GT(bricks, 64u);  // more bricks than passes: the budget would have bound
  FakeBrickSource fake2 = makeScene();
  WorkingSet ws(fake2, cfg);
  bool converged = false;
  uint64_t frames = 0;
  for (; frames < 4 * bricks && !converged; ++frames) {
    const WorkingSetFrame f = ws.update(in);
    EXPECT_LE(f.stats.bricksUploaded, 1u);
    converged = f.converged;
    if (!converged) ws.waitForReads(std::chrono::milliseconds(1000));
  }
  EXPECT_TRUE(converged) << "not converged after " << frames << " frames for " << bricks << " bricks";
  EXPECT_EQ(cutOf(reference), cutOf(ws.update(in)));
}

std::set<NodeKey, KeyLess> residentKeys(const WorkingSet& ws) {
  std::set<NodeKey, KeyLess> keys;
  for (uint32_t s = 0; s < ws.slots().slotCount(); ++s) {
    if (const auto k = ws.slots().keyOf(s)) keys.insert(*k);
  }
  return keys;
}

TEST(WorkingSet, BricksTheRaysUseStayInAPoolTooSmallForTheWorkingSet) {
  // Two opposite views whose trees do not fit the pool together; the feedback says that the same 12 bricks of
  // the first view, none in the second's tree, are used in every frame. The pool holds the larger tree and
  // those 12.
  FakeBrickSource src = makeScene();
  FrameInput a = frameFrom({-60, -60, -60}, 60, {20, 20, 20});
  FrameInput b = frameFrom({188, 188, 188}, 60, {108, 108, 108});
  a.isEmpty = b.isEmpty = isoEmpty;
  WorkingSetConfig big = config(2000);
  big.cpuCacheBytes = 2000 * src.brickBytes();
  WorkingSet measureA(src, big), measureB(src, big);
  ASSERT_TRUE(measureA.updateUntilConverged(a).converged);
  ASSERT_TRUE(measureB.updateUntilConverged(b).converged);
  const auto treeA = residentKeys(measureA), treeB = residentKeys(measureB);
  std::vector<NodeKey> used;
  for (const NodeKey& k : treeA) {
    if (!treeB.count(k) && used.size() < 12) used.push_back(k);
  }
  ASSERT_EQ(used.size(), 12u);
  std::set<NodeKey, KeyLess> all = treeA;
  all.insert(treeB.begin(), treeB.end());
  WorkingSetConfig cfg = big;
  cfg.gpuSlots = uint32_t(std::max(treeA.size(), treeB.size()) + used.size());
  ASSERT_LT(cfg.gpuSlots, all.size());  // the pool is smaller than the working set of both views

  struct Outcome {
    uint64_t usedEvictions = 0;  // as the loader counted them
    uint64_t unusedEvicted = 0;  // bricks not in `used` that left the pool
    uint64_t usedMissing = 0;    // bricks of `used` not in the pool after a turn to b
  };
  const auto alternate = [&](bool withFeedback) {
    WorkingSet ws(src, cfg);
    Outcome o;
    for (int round = 0; round < 3; ++round) {
      for (FrameInput* in : {&a, &b}) {
        in->usedNodes = withFeedback ? used : std::vector<NodeKey>{};
        const auto before = residentKeys(ws);
        const WorkingSetFrame f = ws.updateUntilConverged(*in);
        EXPECT_TRUE(f.converged);
        o.usedEvictions += f.stats.usedBricksEvicted;
        const auto after = residentKeys(ws);
        for (const NodeKey& k : before) {
          if (!after.count(k) && std::find(used.begin(), used.end(), k) == used.end()) ++o.unusedEvicted;
        }
        if (in == &b) {
          for (const NodeKey& k : used) o.usedMissing += !after.count(k);
        }
      }
    }
    return o;
  };
  const Outcome withFeedback = alternate(true);
  EXPECT_EQ(withFeedback.usedEvictions, 0u);
  EXPECT_EQ(withFeedback.usedMissing, 0u);
  EXPECT_GT(withFeedback.unusedEvicted, 0u);  // the pool was too small: the unused bricks made room
  // Without feedback, eviction by residency takes some of them whenever the camera turns to b.
  EXPECT_GT(alternate(false).usedMissing, 0u);
}

TEST(WorkingSet, BricksOfHiddenNodesAreReusedBeforeThoseThatLeftTheCutEarlier) {
  // Three views in turn, a, b, c, in a pool 12 bricks smaller than their trees together. Turning to c, the
  // pool's least recently used bricks are those that left the cut at the turn to b (only in a's tree). Hidden
  // are: nodes only in b's tree with their parents (they leave the cut now), nodes only in b's tree without
  // their parents, and the nodes of b's tree that c's keeps. The pool reuses the slots of the first kind, the
  // hidden nodes below a hidden node that left the cut, and no other; three of them the rays used, and those
  // stay (use wins).
  FakeBrickSource src = makeScene();
  FrameInput a = frameFrom({-60, -60, -60}, 60, {20, 20, 20});
  FrameInput b = frameFrom({188, 188, 188}, 60, {108, 108, 108});
  FrameInput c = frameFrom({188, -60, -60}, 60, {108, 20, 20});
  a.isEmpty = b.isEmpty = c.isEmpty = isoEmpty;
  WorkingSetConfig big = config(2000);
  big.cpuCacheBytes = 2000 * src.brickBytes();
  const auto treeOf = [&](const FrameInput& in) {
    WorkingSet measure(src, big);
    EXPECT_TRUE(measure.updateUntilConverged(in).converged);
    return residentKeys(measure);
  };
  const auto treeA = treeOf(a), treeB = treeOf(b), treeC = treeOf(c);
  std::set<NodeKey, KeyLess> all = treeA, onlyA, onlyB, onlyC, hidden;
  all.insert(treeB.begin(), treeB.end());
  all.insert(treeC.begin(), treeC.end());
  for (const NodeKey& k : all) {
    const int in = int(treeA.count(k)) + 2 * int(treeB.count(k)) + 4 * int(treeC.count(k));
    if (in == 1) onlyA.insert(k);
    if (in == 2) onlyB.insert(k);
    if (in == 4) onlyC.insert(k);
    if (in == 6) hidden.insert(k);  // in b's tree and c's
  }
  size_t withParent = 0;
  for (auto it = onlyB.begin(); it != onlyB.end() && withParent < 16; ++it, ++withParent)
    hidden.insert({*it, it->parent()});
  std::vector<NodeKey> bAlone;
  for (const NodeKey& k : onlyB) {
    if (bAlone.size() < 16 && !hidden.count(k) && !hidden.count(k.parent())) bAlone.push_back(k);
  }
  hidden.insert(bAlone.begin(), bAlone.end());
  std::set<NodeKey, KeyLess> reusable;  // hidden, below a hidden node, leaving the cut
  for (const NodeKey& k : hidden)
    if (onlyB.count(k) && hidden.count(k.parent())) reusable.insert(k);
  const std::vector<NodeKey> used(std::prev(reusable.end(), 3), reusable.end());
  for (const NodeKey& k : used) reusable.erase(k);
  ASSERT_EQ(bAlone.size(), 16u);
  ASSERT_GE(reusable.size(), 12u);
  ASSERT_GT(onlyA.size(), 12u);

  WorkingSetConfig cfg = big;
  cfg.gpuSlots = uint32_t(all.size() - 12);
  for (const bool withHidden : {false, true}) {
    WorkingSet ws(src, cfg);
    ASSERT_TRUE(ws.updateUntilConverged(a).converged);
    ASSERT_TRUE(ws.updateUntilConverged(b).converged);
    const auto before = residentKeys(ws);
    ASSERT_EQ(before.size(), all.size() - onlyC.size());  // nothing evicted yet
    c.hiddenNodes = withHidden ? std::vector<NodeKey>(hidden.begin(), hidden.end()) : std::vector<NodeKey>{};
    c.usedNodes = withHidden ? used : std::vector<NodeKey>{};
    const WorkingSetFrame f = ws.updateUntilConverged(c);
    ASSERT_TRUE(f.converged);
    const auto after = residentKeys(ws);
    std::set<NodeKey, KeyLess> evicted;
    for (const NodeKey& k : before)
      if (!after.count(k)) evicted.insert(k);
    EXPECT_EQ(evicted.size(), 12u);
    EXPECT_EQ(f.stats.bricksUploaded, onlyC.size());  // nothing uploaded twice
    EXPECT_EQ(f.stats.usedBricksEvicted, 0u);
    for (const NodeKey& k : evicted) {
      if (withHidden)
        EXPECT_TRUE(reusable.count(k)) << "reused the brick of a node not hidden, or in c's tree, or alone";
      else
        EXPECT_TRUE(onlyA.count(k)) << "by recency alone, the bricks that left the cut first go first";
    }
  }
}

TEST(WorkingSet, AFullPoolWithHintsFillsTheSlotsAHiddenNodeFreesWithoutWaitingForTheDisk) {
  // Progressive frames with hints (none says anything yet) in a pool too small for the view, until the cut
  // settles and nothing is pending. Then a refined node is hidden: its children's slots go to the first
  // node the pool had no room for, whose bricks were read while the pool was full, so the same frame uploads
  // them and nothing is requested. Without that read-ahead the node would wait a frame for the disk.
  FakeBrickSource src = makeScene();
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  in.hints = [](const NodeKey&) { return NodeHint::None; };
  WorkingSetConfig cfg = config(/*slots=*/60);
  cfg.cpuCacheBytes = 400 * src.brickBytes();
  WorkingSet ws(src, cfg);
  WorkingSetFrame settled;
  for (int frame = 0; frame < 100; ++frame) {
    settled = ws.update(in);
    if (settled.converged && ws.io().pendingCount() == 0) break;
    ws.waitForReads(std::chrono::seconds(1));
  }
  ASSERT_TRUE(settled.converged);
  ASSERT_EQ(ws.io().pendingCount(), 0u);
  const auto firstPoolFull =
      std::find_if(settled.leaves.begin(), settled.leaves.end(),
                   [](const PlannedLeaf& l) { return l.reason == LeafReason::PoolFull; });
  ASSERT_NE(firstPoolFull, settled.leaves.end());
  const NodeKey waiting = firstPoolFull->key;
  // A refined node, not above the waiting one, whose eight children are leaves with bricks.
  std::map<NodeKey, int, KeyLess> brickChildren;
  for (const PlannedLeaf& l : settled.leaves)
    if (l.content == LeafContent::Brick && l.key.depth > 0) ++brickChildren[l.key.parent()];
  std::optional<NodeKey> hidden;
  for (const auto& [parent, count] : brickChildren) {
    NodeKey a = waiting;
    while (a.depth > parent.depth) a = a.parent();
    if (count == 8 && a != parent) hidden = parent;
  }
  ASSERT_TRUE(hidden);

  FrameInput hiding = in;
  hiding.hints = [&](const NodeKey& k) { return k == *hidden ? NodeHint::Occluded : NodeHint::None; };
  const WorkingSetFrame f = ws.update(hiding);
  EXPECT_EQ(f.stats.cacheMisses, 0u);
  EXPECT_TRUE(f.converged);
  const auto cut = cutOf(f);
  EXPECT_FALSE(cut.count(waiting)) << "the waiting node was not refined";
  for (uint32_t o = 0; o < 8; ++o) EXPECT_TRUE(cut.count(waiting.child(o)));
}

TEST(WorkingSet, AColdStartReadsTheTreeWithoutWaitingForFrames) {
  // The first update finds nothing in core; the workers then read every brick the view needs while no
  // update() is called, and the next update refines the whole tree at once.
  FakeBrickSource fake = makeScene();
  WorkingSetConfig cfg = config(2000);
  cfg.cpuCacheBytes = 2000 * fake.brickBytes();
  WorkingSet ws(fake, cfg);
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  in.isEmpty = isoEmpty;
  const WorkingSetFrame first = ws.update(in);
  ASSERT_FALSE(first.converged);
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (ws.io().pendingCount() > 0 && std::chrono::steady_clock::now() < end)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  ASSERT_EQ(ws.io().pendingCount(), 0u);

  const WorkingSetFrame second = ws.update(in);
  EXPECT_TRUE(second.converged);
  FakeBrickSource fake2 = makeScene();
  WorkingSet sync(fake2, cfg);
  EXPECT_EQ(cutOf(second), cutOf(sync.updateUntilConverged(in)));
  EXPECT_EQ(sync.frameCount(), 2u);  // one wave of reads
  // Every brick read was used: nothing read ahead was wasted.
  uint64_t dataUploads = 0;
  for (const BrickUpload& u : second.uploads) dataUploads += fake.node(u.key).kind == NodeKind::Data;
  EXPECT_EQ(fake.reads(), dataUploads);
}

TEST(WorkingSet, APrefetchReadsWhatTheFirstUpdateAsksForWithoutPlanningAFrame) {
  // A pool that holds the view, and one that fills (the reads stop at its room in both).
  for (const uint32_t slots : {2000u, 40u}) {
    SCOPED_TRACE("slots " + std::to_string(slots));
    WorkingSetConfig cfg = config(slots);
    cfg.cpuCacheBytes = 2000 * 46656;  // no CPU eviction: every read is a first read
    FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
    in.isEmpty = isoEmpty;
    const auto readSet = [](const FakeBrickSource& f) {
      const std::vector<NodeKey> order = f.readOrder();
      return std::set<NodeKey, KeyLess>(order.begin(), order.end());
    };

    FakeBrickSource updated = makeScene();
    WorkingSet first(updated, cfg);
    const WorkingSetFrame firstFrame = first.update(in);
    ASSERT_TRUE(first.waitForReads(std::chrono::seconds(10)));

    FakeBrickSource prefetched = makeScene();
    WorkingSet ws(prefetched, cfg);
    ws.prefetch(in);
    ASSERT_TRUE(ws.waitForReads(std::chrono::seconds(10)));
    EXPECT_EQ(ws.frameCount(), 0u);
    EXPECT_EQ(ws.slots().occupiedCount(), 0u);
    ASSERT_GT(prefetched.reads(), 8u);  // the read-ahead too, not only the root's children
    EXPECT_EQ(readSet(prefetched), readSet(updated));

    // Its first frame is the second one of a renderer that did not prefetch.
    const WorkingSetFrame f = ws.update(in);
    const WorkingSetFrame second = first.update(in);
    EXPECT_EQ(cutOf(f), cutOf(second));
    EXPECT_EQ(f.uploads.size(), second.uploads.size() + firstFrame.uploads.size());
    EXPECT_EQ(f.converged, second.converged);
  }
}

TEST(WorkingSet, ReadsOnlyWhatTheGpuPoolHasRoomFor) {
  FakeBrickSource fake = makeScene();
  WorkingSetConfig cfg = config(/*slots=*/40);
  cfg.cpuCacheBytes = 400 * fake.brickBytes();  // no CPU eviction: every read is a first read
  WorkingSet ws(fake, cfg);
  FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
  const WorkingSetFrame f = ws.updateUntilConverged(in);
  ASSERT_TRUE(f.converged);
  // Requests beyond the pool's room are never made: slots wanted by waiting nodes are reserved in priority
  // order. Allow one node's children of slack for the frame in which the pool fills.
  EXPECT_LE(fake.reads(), cfg.gpuSlots + 8u);
  EXPECT_EQ(ws.slots().occupiedCount(), f.stats.bricksResident);
}

TEST(WorkingSet, ASynchronousLoadWithHintsReadsNothingBelowWhatThePoolHasNoRoomFor) {
  // The read-ahead below a full pool's leaves is for progressive frames, whose later answers free slots; a
  // synchronous load has no answers, so with hints it reads exactly what it reads without.
  std::vector<uint64_t> reads;
  for (const bool withHints : {false, true}) {
    FakeBrickSource fake({256, 256, 256}, 16);
    WorkingSetConfig cfg = config(/*slots=*/320);  // room for 10 bricks below the full pool's leaves
    cfg.cpuCacheBytes = 2000 * fake.brickBytes();
    WorkingSet ws(fake, cfg);
    FrameInput in = frameFrom({128 + 300, 128 - 180, 128 + 120}, 800, {128, 128, 128});
    if (withHints) in.hints = [](const NodeKey&) { return NodeHint::None; };
    const WorkingSetFrame f = ws.updateUntilConverged(in);
    ASSERT_TRUE(f.converged);
    ASSERT_GT(f.stats.leavesPoolFull, 2u);
    ws.waitForReads(std::chrono::seconds(1));
    reads.push_back(fake.reads());
  }
  EXPECT_EQ(reads[0], reads[1]);
}

TEST(WorkingSet, ConstantNodesAreUploadedAsFilledBricksWithoutReads) {
  // Everything is constant below the root: only the root is read.
  FakeBrickSource src({64, 64, 64}, 16, [](const NodeKey& k) -> NodeInfo {
    if (k.depth == 0) return {NodeKind::Data, 7, 150};
    return {NodeKind::Constant, 7, 7};
  });
  WorkingSet ws(src, config(100));
  const WorkingSetFrame f = ws.updateUntilConverged(frameFrom({32, 32, -10}, 2000, {32, 32, 32}));
  ASSERT_TRUE(f.converged);
  EXPECT_EQ(src.reads(), 1u);
  size_t constants = 0;
  for (const PlannedLeaf& l : f.leaves) {
    if (l.reason != LeafReason::Constant) continue;
    ++constants;
    EXPECT_EQ(l.key.depth, 1u);  // constant nodes are not refined
  }
  EXPECT_EQ(constants, 8u);
  for (const BrickUpload& u : f.uploads) {
    if (u.key.depth == 1) {
      EXPECT_EQ((*u.brick)[100], std::byte{7});
    }
  }
}

TEST(WorkingSet, ShutsDownWithReadsInFlight) {
  FakeBrickSource fake = makeScene();
  DelayedBrickSource slow(fake, 30.0);
  const auto start = SteadyClock::now();
  {
    WorkingSet ws(slow, config());
    FrameInput in = frameFrom({64 + 150, 64 - 90, 64 + 60});
    for (int i = 0; i < 3; ++i) {
      ws.update(in);
      std::this_thread::sleep_for(std::chrono::milliseconds(35));
    }
    EXPECT_GT(ws.io().pendingCount(), 0u);
  }
  const double ms = millisecondsSince(start);
  EXPECT_LT(ms, 1000.0);
}

TEST(WorkingSet, AFailedReadIsReportedWithTheNode) {
  FakeBrickSource src = makeScene();
  src.failOn(NodeKey{1, {1, 0, 1}});
  WorkingSet ws(src, config());
  try {
    ws.updateUntilConverged(frameFrom({64 + 150, 64 - 90, 64 + 60}));
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("depth 1, 1,0,1"), std::string::npos) << e.what();
  }
}

TEST(WorkingSet, RejectsBudgetsThatCannotWork) {
  FakeBrickSource src = makeScene();
  WorkingSetConfig c = config();
  c.uploadBudgetBytes = src.brickBytes() - 1;
  EXPECT_THROW(WorkingSet(src, c), UsageError);  // exit 2 in the CLI
  c = config(0);  // a pool of no slots: a caller's mistake, not an option's (BrickPool refuses such budgets)
  EXPECT_THROW(WorkingSet(src, c), Error);
  c = config();
  c.cpuCacheBytes = 10;  // below one brick too: the message gives the least that works
  try {
    WorkingSet ws(src, c);
    ADD_FAILURE() << "a CPU cache of 10 bytes was taken";
  } catch (const UsageError& e) {
    EXPECT_EQ(std::string(e.what()), "--cpu-cache 10 bytes is below 16 bricks of " +
                                         std::to_string(src.brickBytes()) + " bytes (" +
                                         std::to_string(16 * src.brickBytes()) +
                                         " bytes: the children of a few nodes must fit at once)");
  }
}

}  // namespace
}  // namespace ropecast
