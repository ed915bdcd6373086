// Footprint probes (terrain/view/texel_footprint.h): one probe where the
// footprint is square, probes along the longer axis at the width's level
// where it is not, no gaps between them, and never beyond a tile's border.
#include "aperture/terrain/view/texel_footprint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include <glm/geometric.hpp>

namespace aal {
namespace {

TEST(TexelFootprint, ASquareFootprintIsOneProbeAtItsLevel) {
  const FootprintProbes p = footprintProbes({4.0f, 0.0f}, {0.0f, 4.0f});
  EXPECT_EQ(p.count, 1);
  EXPECT_FLOAT_EQ(p.lod, 2.0f);
  // Turned on the DEM (a view along a diagonal) it is still square.
  const FootprintProbes turned = footprintProbes({2.4f, 3.2f}, {-3.2f, 2.4f});
  EXPECT_EQ(turned.count, 1);
  EXPECT_NEAR(turned.lod, 2.0f, 1e-6f);
}

TEST(TexelFootprint, AnOneByFourFootprintIsFourProbesAtTheWidthsLevel) {
  // One texel across, four down the screen: four level-0 probes a texel
  // apart along the longer axis, centred on the fragment.
  const FootprintProbes p = footprintProbes({1.0f, 0.0f}, {0.0f, 4.0f});
  EXPECT_EQ(p.count, 4);
  EXPECT_FLOAT_EQ(p.lod, 0.0f);
  EXPECT_FLOAT_EQ(p.step.x, 0.0f);
  EXPECT_FLOAT_EQ(p.step.y, 1.0f);
  const FootprintProbes coarse = footprintProbes({0.0f, 8.0f}, {-2.0f, 0.0f});
  EXPECT_EQ(coarse.count, 4);
  EXPECT_FLOAT_EQ(coarse.lod, 1.0f);
  EXPECT_FLOAT_EQ(coarse.step.y, 2.0f);
}

TEST(TexelFootprint, ASheeredFootprintIsReadAtItsWidthNotItsShorterDerivative) {
  // Both derivatives about 2 texels long but nearly parallel: the footprint
  // is a thin parallelogram 0.49 texels wide. The shorter derivative's level
  // (1, as a GPU's anisotropic filter takes it) would blur it across.
  const FootprintProbes p = footprintProbes({2.0f, 0.0f}, {2.0f, 0.5f});
  EXPECT_EQ(p.count, 4);  // |L| / W = 2.06 / 0.485 = 4.25, at most 4
  EXPECT_FLOAT_EQ(p.lod, 0.0f);
  EXPECT_NEAR(glm::length(p.step), std::sqrt(4.25f) / 4.0f, 1e-6f);
}

TEST(TexelFootprint, BeyondTheLargestRatioTheLevelRisesSoTheProbesLeaveNoGaps) {
  // 16:1 with at most four probes: they sit four texels apart, so they are
  // read at level 2, whose texels are four wide.
  const FootprintProbes p = footprintProbes({1.0f, 0.0f}, {0.0f, 16.0f});
  EXPECT_EQ(p.count, kMaxFootprintProbes);
  EXPECT_FLOAT_EQ(p.lod, 2.0f);
  EXPECT_FLOAT_EQ(p.step.y, 4.0f);
}

// Random footprints from 1/100 to 1000 texels across, any anisotropy and
// orientation.
template <typename Check>
void forRandomFootprints(Check check) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> angle(0.0f, 6.2831853f), exponent(-2.0f, 3.0f),
      ratio(0.0f, 6.0f), shear(-1.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) {
    const float length = std::pow(10.0f, exponent(rng)), a = angle(rng);
    const glm::vec2 along(std::cos(a), std::sin(a)), across(-along.y, along.x);
    const glm::vec2 dx = length * along;
    const glm::vec2 dy = length * (shear(rng) * along + std::exp2(-ratio(rng)) * across);
    check(dx, dy, footprintProbes(i % 2 ? dx : dy, i % 2 ? dy : dx));
  }
}

TEST(TexelFootprint, ProbesSpanTheLongerAxisWithoutGaps) {
  forRandomFootprints([](glm::vec2 dx, glm::vec2 dy, const FootprintProbes& p) {
    ASSERT_GE(p.count, 1);
    ASSERT_LE(p.count, kMaxFootprintProbes);
    ASSERT_GE(p.lod, 0.0f);
    const float major = std::max(glm::length(dx), glm::length(dy));
    const float spacing = glm::length(p.step);
    // Never farther apart than the level's texels (nothing between them is
    // skipped) ...
    EXPECT_LE(spacing, std::exp2(p.lod) * 1.0001f + 1e-6f);
    // ... and together as long as the longer axis, unless the tile border
    // shortened them (below).
    const float offset = 0.5f * float(p.count - 1) * spacing;
    const float coarser = std::exp2(std::min(std::floor(p.lod) + 1.0f, 5.0f));
    if (offset < AAL_TERRAIN_TILE_BORDER - 1.5f * coarser - 1e-3f) {
      EXPECT_NEAR(spacing * float(p.count), major, 1e-4f * major);
    }
  });
}

TEST(TexelFootprint, TheOutermostProbeStaysWithinATilesBorder) {
  // Each texture is looked up in its tile once per fragment: the probes'
  // bilinear footprints (1.5 texels of the coarser level of a trilinear
  // fetch) must stay within the border beyond the tile's core.
  int shortened = 0;
  forRandomFootprints([&](glm::vec2, glm::vec2, const FootprintProbes& p) {
    const float offset = 0.5f * float(p.count - 1) * glm::length(p.step);
    const float level = std::min(std::floor(p.lod) + 1.0f, float(AAL_TERRAIN_MIP_LEVELS - 1));
    EXPECT_LE(offset + 1.5f * std::exp2(level), AAL_TERRAIN_TILE_BORDER * 1.0001f);
    if (offset > 0 && offset + 1.5f * std::exp2(level) > AAL_TERRAIN_TILE_BORDER - 0.01f) {
      ++shortened;
    }
  });
  EXPECT_GT(shortened, 0) << "the random footprints must reach the border";
}

TEST(TexelFootprint, FewerProbesReadACoarserLevelAndOneIsTheLongerAxisLevel) {
  // 1 x 16 texels: four probes at level 2 (4 texels apart), two at level 3,
  // one at level 4, the longer axis' (a GPU's isotropic trilinear fetch).
  for (int most = 1; most <= kMaxFootprintProbes; ++most) {
    const FootprintProbes p = footprintProbes({1.0f, 0.0f}, {0.0f, 16.0f}, most);
    EXPECT_EQ(p.count, most);
    EXPECT_FLOAT_EQ(p.lod, std::log2(16.0f / float(most)));
    EXPECT_FLOAT_EQ(glm::length(p.step), 16.0f / float(most));
  }
  forRandomFootprints([](glm::vec2 dx, glm::vec2 dy, const FootprintProbes&) {
    const FootprintProbes one = footprintProbes(dx, dy, 1);
    ASSERT_EQ(one.count, 1);
    const float major = std::max(glm::length(dx), glm::length(dy));
    EXPECT_NEAR(one.lod, std::max(0.0f, std::log2(major)), 1e-5f);
    // Out-of-range limits are clamped to 1..kMaxFootprintProbes.
    EXPECT_EQ(footprintProbes(dx, dy, 0).count, 1);
    EXPECT_EQ(footprintProbes(dx, dy, 99).count, footprintProbes(dx, dy).count);
  });
}

TEST(TexelFootprint, DegenerateDerivativesAreOneProbeAtLevelZero) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (const auto& [dx, dy] : {std::pair{glm::vec2(0.0f), glm::vec2(0.0f)},
                               std::pair{glm::vec2(nan, 0.0f), glm::vec2(0.0f, 1.0f)},
                               std::pair{glm::vec2(inf, 0.0f), glm::vec2(0.0f, 1.0f)}}) {
    const FootprintProbes p = footprintProbes(dx, dy);
    EXPECT_EQ(p.count, 1);
    EXPECT_EQ(p.lod, 0.0f);
  }
  // A footprint with no width (a view along the DEM's plane) is a line:
  // the most probes, at the level that leaves no gaps.
  const FootprintProbes line = footprintProbes({0.0f, 0.0f}, {0.0f, 8.0f});
  EXPECT_EQ(line.count, kMaxFootprintProbes);
  EXPECT_FLOAT_EQ(line.lod, 1.0f);
}

}  // namespace
}  // namespace aal
