// Void filling: nearest valid texel in metres, checked against brute force.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "aperture/terrain/io/void_fill.h"

namespace aal {
namespace {

// Distance in metres from texel i to the texel whose (unique) value is z.
struct Grid {
  int width, height;
  double cellX, cellY;
  double distance(size_t a, size_t b) const {
    const double dx = static_cast<double>(a % width) - static_cast<double>(b % width);
    const double dy = static_cast<double>(a / width) - static_cast<double>(b / width);
    return std::hypot(dx * cellX, dy * cellY);
  }
};

TEST(VoidFill, EachVoidTakesItsNearestValidHeight) {
  std::mt19937 rng(7);
  for (const auto& [cellX, cellY] :
       {std::pair{1.0, 1.0}, std::pair{74.5, 92.5}, std::pair{3.0, 1.0}}) {
    const Grid g{37, 23, cellX, cellY};
    const size_t n = static_cast<size_t>(g.width * g.height);
    std::vector<uint8_t> mask(n);
    std::vector<float> z(n);
    std::bernoulli_distribution isVoid(0.8);
    for (size_t i = 0; i < n; ++i) {
      mask[i] = isVoid(rng) ? 1 : 0;
      z[i] = mask[i] ? -1.0f : static_cast<float>(i);  // unique: the value names its texel
    }
    const std::vector<float> original = z;
    ASSERT_TRUE(fillVoidsNearest(z, mask, g.width, g.height, cellX, cellY));
    double worstExcess = 0;
    for (size_t i = 0; i < n; ++i) {
      if (!mask[i]) {
        EXPECT_EQ(z[i], original[i]);
        continue;
      }
      const auto source = static_cast<size_t>(z[i]);
      ASSERT_LT(source, n);
      ASSERT_EQ(mask[source], 0) << "filled from a void";
      double best = std::numeric_limits<double>::infinity();
      for (size_t j = 0; j < n; ++j) {
        if (!mask[j]) best = std::min(best, g.distance(i, j));
      }
      worstExcess = std::max(worstExcess, g.distance(i, source) - best);
    }
    // The sequential transform is exact but for rare near-ties.
    EXPECT_LE(worstExcess, 0.25 * std::max(cellX, cellY)) << cellX << " x " << cellY;
  }
}

TEST(VoidFill, SingleValidTexelFillsEverything) {
  std::vector<float> z(50, 0.0f);
  std::vector<uint8_t> mask(50, 1);
  mask[37] = 0;
  z[37] = 12.5f;
  ASSERT_TRUE(fillVoidsNearest(z, mask, 10, 5, 1.0, 1.0));
  for (float v : z) EXPECT_EQ(v, 12.5f);
}

TEST(VoidFill, AllVoidReportsFailureAndChangesNothing) {
  std::vector<float> z(6, 3.0f);
  const std::vector<uint8_t> mask(6, 1);
  EXPECT_FALSE(fillVoidsNearest(z, mask, 3, 2, 1.0, 1.0));
  EXPECT_EQ(z, std::vector<float>(6, 3.0f));
}

TEST(VoidFill, NoVoidsChangesNothing) {
  std::vector<float> z = {1, 2, 3, 4};
  EXPECT_TRUE(fillVoidsNearest(z, std::vector<uint8_t>(4, 0), 2, 2, 1.0, 1.0));
  EXPECT_TRUE(fillVoidsNearest(z, {}, 2, 2, 1.0, 1.0));
  EXPECT_EQ(z, (std::vector<float>{1, 2, 3, 4}));
}

TEST(VoidFill, MismatchedSizesThrow) {
  std::vector<float> z(4);
  EXPECT_THROW(fillVoidsNearest(z, std::vector<uint8_t>(3, 1), 2, 2, 1, 1), std::invalid_argument);
}

}  // namespace
}  // namespace aal
