// The shimmer measure (terrain/reference/shimmer.h) on sequences whose
// temporal second difference is known.
#include "aperture/terrain/reference/shimmer.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

namespace aal {
namespace {

// A grey frame of `count` pixels at luminance `y` (R = G = B).
std::vector<glm::vec3> grey(size_t count, float y) {
  return std::vector<glm::vec3>(count, glm::vec3(y));
}

TEST(Shimmer, AStillSequenceReadsZero) {
  ShimmerMeter meter;
  const std::vector<uint8_t> all(16, 1);
  for (int t = 0; t < 5; ++t) meter.addFrame(grey(16, 3.0f), all);
  EXPECT_EQ(meter.frames(), 5);
  EXPECT_EQ(meter.terms(), 3u * 16u);
  EXPECT_EQ(meter.meanSecondDifference(), 0.0);
}

TEST(Shimmer, ASteadyChangeReadsZero) {
  // Luminance linear in time: the second difference vanishes, however fast.
  ShimmerMeter meter;
  const std::vector<uint8_t> all(4, 1);
  for (int t = 0; t < 6; ++t) meter.addFrame(grey(4, 1.0f + 0.5f * float(t)), all);
  EXPECT_NEAR(meter.meanSecondDifference(), 0.0, 1e-6);
}

TEST(Shimmer, AFlickerReadsFourTimesItsAmplitude) {
  // 2 + a, 2 - a, 2 + a, ...: |(2+a) - 2(2-a) + (2+a)| = 4a at every frame.
  ShimmerMeter meter;
  const std::vector<uint8_t> all(8, 1);
  for (int t = 0; t < 7; ++t) meter.addFrame(grey(8, t % 2 == 0 ? 2.25f : 1.75f), all);
  EXPECT_NEAR(meter.meanSecondDifference(), 1.0, 1e-6);
}

TEST(Shimmer, CountsOnlyPixelsInEveryFrameOfTheTriple) {
  // Pixel 0 flickers but leaves the mask in the third frame; pixel 1 stays
  // still and counted: only the still pixel's terms count.
  ShimmerMeter meter;
  const std::vector<float> flicker = {5.0f, 1.0f, 5.0f, 1.0f};
  for (int t = 0; t < 4; ++t) {
    const std::vector<glm::vec3> frame = {glm::vec3(flicker[t]), glm::vec3(2.0f)};
    meter.addFrame(frame, {uint8_t(t == 2 ? 0 : 1), 1});
  }
  EXPECT_EQ(meter.terms(), 2u);  // pixel 1 at t = 1 and t = 2
  EXPECT_EQ(meter.meanSecondDifference(), 0.0);
}

TEST(Shimmer, LuminanceWeighsTheChannels) {
  // Only green changes: the measure sees 0.7152 of it (Rec. 709 Y).
  ShimmerMeter meter;
  const std::vector<uint8_t> one(1, 1);
  for (int t = 0; t < 3; ++t) {
    meter.addFrame({glm::vec3(1.0f, t == 1 ? 2.0f : 1.0f, 1.0f)}, one);
  }
  EXPECT_NEAR(meter.meanSecondDifference(), 2.0 * 0.7152, 1e-4);
}

TEST(Shimmer, FramesOfAnotherSizeAreRefused) {
  ShimmerMeter meter;
  meter.addFrame(grey(4, 1.0f), std::vector<uint8_t>(4, 1));
  EXPECT_THROW(meter.addFrame(grey(5, 1.0f), std::vector<uint8_t>(5, 1)), std::invalid_argument);
  EXPECT_THROW(meter.addFrame(grey(4, 1.0f), std::vector<uint8_t>(3, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace aal
