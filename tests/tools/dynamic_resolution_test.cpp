// aal-view's dynamic resolution policy (tools/viewer/dynamic_resolution.h).
#include <gtest/gtest.h>

#include <cmath>

#include "aperture/tools/viewer/dynamic_resolution.h"

namespace aal {
namespace {

// A frame whose time is `fixedMs` plus `pixelMs` at full resolution, scaled
// by the pixels drawn.
double frameMs(float scale, double fixedMs, double pixelMs) {
  return fixedMs + pixelMs * scale * scale;
}

TEST(DynamicResolution, OffOrRestingDrawsFullResolution) {
  DynamicResolution off;
  off.frameFinished(500, true);
  EXPECT_EQ(off.scaleFor(true), 1.0f);
  DynamicResolution on(30);
  for (int i = 0; i < 20; ++i) on.frameFinished(100, true);
  EXPECT_LT(on.scaleFor(true), 1.0f);
  EXPECT_EQ(on.scaleFor(false), 1.0f);  // the view rests: full resolution
  on.frameFinished(200, false);         // a resting frame changes nothing
  EXPECT_LT(on.scaleFor(true), 1.0f);
  on.setTargetFps(0);
  EXPECT_EQ(on.scaleFor(true), 1.0f);
}

TEST(DynamicResolution, SettlesWhereTheTargetIsMet) {
  DynamicResolution d(30);  // 33.3 ms
  float scale = 1;
  for (int i = 0; i < 60; ++i) {
    scale = d.scaleFor(true);
    d.frameFinished(frameMs(scale, 12, 60), true);
  }
  // 12 + 60 s^2 = 33.3 at s = 0.60; the controller stays within its dead band
  // (0.8 .. 1.05 of the target) without oscillating out of it.
  const double ms = frameMs(scale, 12, 60);
  EXPECT_GT(ms, 0.8 * 33.3 * 0.95);
  EXPECT_LT(ms, 1.05 * 33.3);
  for (int i = 0; i < 10; ++i) {
    const float before = d.scaleFor(true);
    d.frameFinished(frameMs(before, 12, 60), true);
    EXPECT_NEAR(d.scaleFor(true), before, 0.05f);
  }
}

TEST(DynamicResolution, NeverDropsBelowAQuarterOfThePixelsAndRecovers) {
  DynamicResolution d(1000);  // unreachable
  for (int i = 0; i < 50; ++i) d.frameFinished(frameMs(d.scaleFor(true), 12, 60), true);
  EXPECT_EQ(d.scaleFor(true), DynamicResolution::kMinimumScale);
  d.setTargetFps(5);  // easy
  for (int i = 0; i < 50; ++i) d.frameFinished(frameMs(d.scaleFor(true), 12, 60), true);
  EXPECT_EQ(d.scaleFor(true), 1.0f);
}

// Rebuilt from the frames before, the scale may fall to a third of the
// width; scaled up again, it rises back to half at once.
TEST(DynamicResolution, RebuiltFramesMayDropToAThirdOfTheWidth) {
  DynamicResolution d(1000);  // unreachable
  d.setRebuilt(true);
  EXPECT_EQ(d.minimumScale(), DynamicResolution::kRebuiltMinimumScale);
  for (int i = 0; i < 50; ++i) d.frameFinished(frameMs(d.scaleFor(true), 12, 60), true);
  EXPECT_EQ(d.scaleFor(true), DynamicResolution::kRebuiltMinimumScale);
  EXPECT_LT(DynamicResolution::kRebuiltMinimumScale, DynamicResolution::kMinimumScale);
  d.setRebuilt(false);
  EXPECT_EQ(d.scaleFor(true), DynamicResolution::kMinimumScale);
  for (int i = 0; i < 50; ++i) d.frameFinished(frameMs(d.scaleFor(true), 12, 60), true);
  EXPECT_EQ(d.scaleFor(true), DynamicResolution::kMinimumScale);
}

TEST(DynamicResolution, IgnoresNonsense) {
  DynamicResolution d(std::nan(""));
  EXPECT_EQ(d.targetFps(), 0);
  d.setTargetFps(30);
  d.frameFinished(std::nan(""), true);
  d.frameFinished(-5, true);
  EXPECT_EQ(d.scaleFor(true), 1.0f);
}

}  // namespace
}  // namespace aal
