// StepPacer: the adaptive sample distance of --target-frame-ms, against a ray cast whose cost is inversely
// proportional to the step.
#include <cmath>

#include <gtest/gtest.h>

#include "render/step_pacer.h"

namespace ropecast {
namespace {

// One frame of a scene whose ray cast costs `costAtScale1` ms at the requested step, plus `restMs`.
void renderFrame(StepPacer& pacer, double costAtScale1, double restMs = 0.0) {
  const double raycast = costAtScale1 / pacer.scale();
  pacer.record(raycast + restMs, raycast);
}

TEST(StepPacer, OffKeepsTheRequestedStep) {
  StepPacer pacer(0.0);
  EXPECT_FALSE(pacer.enabled());
  renderFrame(pacer, 500.0);
  EXPECT_EQ(pacer.scale(), 1.0);
}

TEST(StepPacer, ACheapViewKeepsTheRequestedStep) {
  StepPacer pacer(50.0);
  for (int i = 0; i < 10; ++i) renderFrame(pacer, 30.0, 5.0);
  EXPECT_EQ(pacer.scale(), 1.0);
}

TEST(StepPacer, AnExpensiveViewMeetsTheTargetFromTheNextFrame) {
  StepPacer pacer(50.0);
  renderFrame(pacer, 150.0, 10.0);  // 160 ms: 40 ms left for a 150 ms ray cast
  EXPECT_NEAR(pacer.scale(), 150.0 / 40.0, 1e-9);
  const double next = 150.0 / pacer.scale() + 10.0;
  EXPECT_NEAR(next, 50.0, 1e-9);
  for (int i = 0; i < 5; ++i) renderFrame(pacer, 150.0, 10.0);
  EXPECT_NEAR(pacer.scale(), 150.0 / 40.0, 1e-9);  // steady, no oscillation
}

TEST(StepPacer, ARisingCostIsMetFromTheThirdFrame) {
  // A camera closing in: the ray cast at scale 1 costs 10 ms more every frame. From the third frame the pacer
  // extrapolates the rise, so no later frame overruns the target by the rise of one frame.
  StepPacer pacer(50.0);
  for (int i = 0; i < 30; ++i) {
    const double cost = 40.0 + 10.0 * i;
    const double frame = cost / pacer.scale();
    if (i >= 2 && cost < 4.0 * 50.0) {
      EXPECT_LE(frame, 50.0 + 1e-9) << "frame " << i;
    }
    pacer.record(frame, frame);
  }
}

TEST(StepPacer, TheStepIsBounded) {
  StepPacer pacer(10.0);
  renderFrame(pacer, 1000.0);
  EXPECT_EQ(pacer.scale(), StepPacer::kMaxScale);
  // Loading alone overruns the target: the ray cast still gets a quarter of it, not the maximum step.
  StepPacer loading(40.0);
  renderFrame(loading, 20.0, 100.0);
  EXPECT_NEAR(loading.scale(), 2.0, 1e-9);
}

TEST(StepPacer, ReturnsGraduallyWhenTheViewGetsCheaper) {
  StepPacer pacer(50.0);
  renderFrame(pacer, 150.0);
  ASSERT_NEAR(pacer.scale(), 3.0, 1e-9);
  renderFrame(pacer, 25.0);  // now half the target at scale 1
  EXPECT_GT(pacer.scale(), 1.0);
  EXPECT_LT(pacer.scale(), 3.0);
  double previous = pacer.scale();
  for (int i = 0; i < 40; ++i) {
    renderFrame(pacer, 25.0);
    EXPECT_LE(pacer.scale(), previous);
    previous = pacer.scale();
  }
  EXPECT_NEAR(pacer.scale(), 1.0, 1e-3);
}

}  // namespace
}  // namespace ropecast
