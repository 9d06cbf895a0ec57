// Verification of a store (`ropecast verify`): reads every node and checks
//   - each payload's checksum and decompression (Store::readBrick),
//   - kinds: Constant has min == max, Empty only below the recorded --discard-below,
//   - the metadata valueRange: the root's range in data units (types mapped over their range: holds it),
//   - ranges: each brick's values inside its node's [min, max], children's ranges inside the parent's, and
//   the
//     node's range exactly the union of its own brick's and its children's,
//   - borders: every border (and out-of-volume padding) sample equals the sample of the node that owns it,
//   - filtering: every inner node's sample equals the rounded 2x2x2 mean of its children's samples.
// Empty nodes have no samples, so checks that would read them are skipped.
//
// Threads: any thread; keeps at most about three rows of bricks of two adjacent depths decoded.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "store/store.h"

namespace ropecast {

struct VerifyReport {
  uint64_t nodesChecked = 0;
  uint64_t problemCount = 0;
  std::vector<std::string> problems;  // the first `maxProblems`, each naming the node
  bool ok() const { return problemCount == 0; }
};

// `progress(nodesDone, nodesTotal)` is called now and then (may be empty).
VerifyReport verifyStore(const Store& store, size_t maxProblems = 20,
                         const std::function<void(uint64_t, uint64_t)>& progress = {});

}  // namespace ropecast
