// The refinement's emptiness test per mode (render/frame_renderer.h emptinessFor): which nodes, by their
// stored value range, the loader may skip without reading them.
#include <gtest/gtest.h>

#include "core/transfer_function.h"
#include "render/frame_renderer.h"

namespace ropecast {
namespace {

BrickSourceInfo uint8Info() {
  BrickSourceInfo info;
  info.storedType = SampleType::UInt8;
  info.mapping = {1.0, 0.0};
  return info;
}

// Opaque white from 100 to 150, transparent below 90 and above 160: a band, as a window on one tissue.
TfTable bandTf() {
  return TfTable::bake(TransferFunction({TfPoint{90, {1, 1, 1, 0}}, TfPoint{100, {1, 1, 1, 1}},
                                         TfPoint{150, {1, 1, 1, 1}}, TfPoint{160, {1, 1, 1, 0}}}),
                       ValueMapping{1.0, 0.0}, 255);
}

TEST(Emptiness, IsoSkipsTheRangesThatMissTheIsovalue) {
  RenderParams params;
  params.mode = RenderMode::Iso;
  params.isoValue = 100.0;
  const EmptinessPredicate isEmpty = emptinessFor(params, uint8Info(), nullptr);
  EXPECT_TRUE(isEmpty(0, 50));
  EXPECT_FALSE(isEmpty(90, 110));
  EXPECT_FALSE(isEmpty(100, 100));
  EXPECT_TRUE(isEmpty(101, 200));
}

// DVR, and a slice, whose one sample shows its value through the function.
TEST(Emptiness, DvrAndSlicesSkipTheRangesTheFunctionLeavesTransparent) {
  const TfTable tf = bandTf();
  for (RenderMode mode : {RenderMode::Dvr, RenderMode::Slice}) {
    RenderParams params;
    params.mode = mode;
    const EmptinessPredicate isEmpty = emptinessFor(params, uint8Info(), &tf);
    EXPECT_TRUE(isEmpty(0, 50)) << renderModeName(mode);
    EXPECT_FALSE(isEmpty(0, 120)) << renderModeName(mode);
    EXPECT_FALSE(isEmpty(120, 130)) << renderModeName(mode);
    EXPECT_TRUE(isEmpty(170, 250)) << renderModeName(mode);
  }
}

// A maximum intensity projection skips a node only when no value up to its maximum has opacity: a node
// whose values lie above the band is not empty, for its maximum hides the band's values behind or before it.
TEST(Emptiness, MipSkipsOnlyTheRangesBelowEveryOpaqueValue) {
  const TfTable tf = bandTf();
  RenderParams params;
  params.mode = RenderMode::Mip;
  const EmptinessPredicate isEmpty = emptinessFor(params, uint8Info(), &tf);
  EXPECT_TRUE(isEmpty(0, 50));
  EXPECT_TRUE(isEmpty(30, 80));
  EXPECT_FALSE(isEmpty(0, 120));
  EXPECT_FALSE(isEmpty(120, 130));
  EXPECT_FALSE(isEmpty(170, 250));
}

// A minimum intensity projection alike, from the other end: a node whose values all lie above every opaque
// value is empty; one whose values lie below the band is not.
TEST(Emptiness, MinIpSkipsOnlyTheRangesAboveEveryOpaqueValue) {
  const TfTable tf = bandTf();
  RenderParams params;
  params.mode = RenderMode::MinIp;
  const EmptinessPredicate isEmpty = emptinessFor(params, uint8Info(), &tf);
  EXPECT_TRUE(isEmpty(170, 250));
  EXPECT_TRUE(isEmpty(200, 255));
  EXPECT_FALSE(isEmpty(120, 200));
  EXPECT_FALSE(isEmpty(120, 130));
  EXPECT_FALSE(isEmpty(0, 50));
}

// An average intensity projection counts every value toward its mean, whatever the transfer function: only a
// node of zeros is empty (the rays count its length alone).
TEST(Emptiness, AipSkipsOnlyZeros) {
  const TfTable tf = bandTf();
  RenderParams params;
  params.mode = RenderMode::Aip;
  const EmptinessPredicate isEmpty = emptinessFor(params, uint8Info(), &tf);
  EXPECT_TRUE(isEmpty(0, 0));
  EXPECT_FALSE(isEmpty(0, 1));
  EXPECT_FALSE(isEmpty(170, 250));  // where the function is transparent
  EXPECT_FALSE(isEmpty(120, 130));
}

TEST(Emptiness, DvrAndProjectionsNeedATransferFunction) {
  for (RenderMode mode :
       {RenderMode::Dvr, RenderMode::Mip, RenderMode::MinIp, RenderMode::Aip, RenderMode::Slice}) {
    RenderParams params;
    params.mode = mode;
    EXPECT_THROW(emptinessFor(params, uint8Info(), nullptr), Error) << renderModeName(mode);
  }
}

}  // namespace
}  // namespace ropecast
