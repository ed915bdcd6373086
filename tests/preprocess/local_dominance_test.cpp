// Local dominance (preprocess/local_dominance.h) against its definition
// evaluated the slow way, and on terrain with known values.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "aperture/preprocess/local_dominance.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/preprocess/bake_test_util.h"

namespace aal {
namespace {

// The definition as RVT states it (Hesse 2016): the DEM padded by the
// outer radius with its edge texels; for every azimuth k * 15° and every
// distance d of the ring, the nearest texel at (d cos a, d sin a); the
// observer's look-down (z + h - z') / d where positive, weighted by the
// ring's area 2d + 1; all over the same sum for a plane, (h / d)(2d + 1)
// per sample.
std::vector<double> dominanceByDefinition(const Heightfield& f, const LocalDominanceOptions& o) {
  const int pad = o.maxRadiusCells, w = f.width + 2 * pad, h = f.height + 2 * pad;
  std::vector<double> padded(size_t(w) * h);
  for (int r = 0; r < h; ++r) {
    for (int c = 0; c < w; ++c) {
      const int col = std::min(std::max(c - pad, 0), f.width - 1);
      const int row = std::min(std::max(r - pad, 0), f.height - 1);
      padded[size_t(r) * w + c] = f.at(col, row);
    }
  }
  std::vector<double> out(f.texelCount());
  for (int row = 0; row < f.height; ++row) {
    for (int col = 0; col < f.width; ++col) {
      const double eye = padded[size_t(row + pad) * w + col + pad] + o.observerHeightM;
      double sum = 0, plane = 0;
      for (int deg = 0; deg < 360; deg += 15) {
        const double a = deg * std::numbers::pi / 180;
        for (int d = o.minRadiusCells; d <= o.maxRadiusCells; ++d) {
          const int c = col + pad + int(std::round(d * std::cos(a)));
          const int r = row + pad + int(std::round(d * std::sin(a)));
          const double below = eye - padded[size_t(r) * w + c];
          if (below > 0) sum += below / d * (2 * d + 1);
          plane += o.observerHeightM / d * (2 * d + 1);
        }
      }
      out[f.index(col, row)] = sum / plane;
    }
  }
  return out;
}

TEST(LocalDominance, EqualsItsDefinition) {
  SyntheticTerrainOptions s;
  s.width = 50;
  s.height = 40;
  s.cellSizeM = 1;
  s.amplitudeM = 6;
  s.featureSizeTexels = 12;
  const Heightfield field = makeSyntheticTerrain(s);
  for (const LocalDominanceOptions& o :
       {LocalDominanceOptions{},
        LocalDominanceOptions{.minRadiusCells = 3, .maxRadiusCells = 7, .observerHeightM = 0.5}}) {
    const std::vector<float> fast = localDominance(field, o);
    const std::vector<double> slow = dominanceByDefinition(field, o);
    double largest = 0;
    for (size_t i = 0; i < fast.size(); ++i) {
      ASSERT_NEAR(fast[i], slow[i], 1e-5 * std::max(1.0, slow[i])) << i;
      largest = std::max(largest, slow[i]);
    }
    EXPECT_GT(largest, 1.5);  // not a flat answer
  }
}

// On a plane gentle enough that the observer looks down on every sample of
// the ring, the uphill and downhill samples cancel: exactly a plane's 1,
// away from the edges (where the edge texels continue flat).
TEST(LocalDominance, IsOneOnAPlane) {
  const Heightfield plane =
      test::makeField(60, 60, 2.0, [](double x, double y) { return 0.02 * x - 0.01 * y; });
  const std::vector<float> ld = localDominance(plane, {});
  for (int row = 20; row < 40; ++row) {
    for (int col = 20; col < 40; ++col) ASSERT_NEAR(ld[plane.index(col, row)], 1.0f, 1e-5f);
  }
}

TEST(LocalDominance, IsAboveOneOnAPeakAndZeroInADeepPit) {
  const Heightfield field = test::makeField(
      61, 61, 1.0, [](double x, double y) { return 20.0 * std::exp(-(x * x + y * y) / 200.0); });
  EXPECT_GT(localDominance(field, {})[field.index(30, 30)], 2.0f);
  Heightfield pit = field;
  for (float& z : pit.z) z = -z;
  EXPECT_EQ(localDominance(pit, {})[pit.index(30, 30)], 0.0f);
}

TEST(LocalDominance, RefusesBadOptions) {
  const Heightfield field = test::makeField(8, 8, 1.0, [](double, double) { return 0.0; });
  for (const LocalDominanceOptions& o :
       {LocalDominanceOptions{.minRadiusCells = 0}, LocalDominanceOptions{.minRadiusCells = 21},
        LocalDominanceOptions{.maxRadiusCells = 1001},
        LocalDominanceOptions{.observerHeightM = 0.0},
        LocalDominanceOptions{.observerHeightM = NAN}}) {
    EXPECT_THROW(localDominance(field, o), std::invalid_argument);
  }
}

}  // namespace
}  // namespace aal
