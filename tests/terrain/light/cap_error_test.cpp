#include "aperture/terrain/light/cap_error.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "aperture/terrain/light/caps.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(CapError, RelativeErrorIsAFractionOfTheSmallerCap) {
  EXPECT_NEAR(capRelativeError(1.0, 1.1, kPi / 2, kPi), 0.1 / (2 * kPi), 1e-12);
  EXPECT_DOUBLE_EQ(capRelativeError(0.0, 0.0, 0.0, 1.0), 0.0);
}

TEST(CapError, SweepCoversTheGridInOrder) {
  const auto samples = sweepCapError(4, 8, kPi);
  ASSERT_EQ(samples.size(), 4u * 4u * 9u);
  EXPECT_DOUBLE_EQ(samples.front().r0Rad, kPi / 4);
  EXPECT_DOUBLE_EQ(samples.front().dRad, 0.0);
  EXPECT_DOUBLE_EQ(samples.back().r0Rad, kPi);
  EXPECT_DOUBLE_EQ(samples.back().dRad, kPi);
}

TEST(CapError, ApproximationErrorStatisticsMatchTheDesignClaims) {
  // docs/caps.md, docs/design.md §2: a few percent of the smaller cap on
  // average and up to ~16% for radii <= pi/2, and much worse once caps exceed a
  // hemisphere.
  const auto samples = sweepCapError(64, 128, kPi);
  const CapErrorSummary half = summarizeCapError(samples, kPi / 2);
  const CapErrorSummary all = summarizeCapError(samples, kPi);
  ASSERT_GT(half.count, 1000u);
  EXPECT_GT(half.meanRelError, 0.005);
  EXPECT_LT(half.meanRelError, 0.05);
  EXPECT_GT(half.maxRelError, 0.10);
  EXPECT_LT(half.maxRelError, 0.20);
  EXPECT_GT(all.maxRelError, 2 * half.maxRelError);
  EXPECT_GT(all.meanRelError, half.meanRelError);
}

TEST(CapError, NoErrorOutsideThePartialOverlap) {
  for (const CapErrorSample& s : sweepCapError(16, 32, kPi / 2)) {
    if (!s.partial) {
      EXPECT_LT(s.relError, 1e-5) << s.r0Rad << " " << s.r1Rad << " " << s.dRad;
    }
  }
}

}  // namespace
}  // namespace aal
