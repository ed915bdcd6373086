// Topographic openness from the bake's sweeps (preprocess/openness.h)
// against direct line tracing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/tests/preprocess/bake_test_util.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kCellM = 10.0;
// A max distance just above 12 cells: the 12th texel along an axis counts
// in the sweep and in the tracing. At exactly 120 m the last bit of the
// sweep's distances along a line would decide.
constexpr double kTwelveCellsM = 120.001;

// 48 x 48 texels of 10 m: a gentle tilt, a bump and a pit.
Heightfield bumpAndPit() {
  return test::makeField(48, 48, kCellM, [](double x, double y) {
    const double bump = 40.0 * std::exp(-((x + 80) * (x + 80) + (y - 60) * (y - 60)) / 3200.0);
    const double pit = -30.0 * std::exp(-((x - 90) * (x - 90) + (y + 70) * (y + 70)) / 1800.0);
    return 0.05 * x + 0.02 * y + bump + pit;
  });
}

struct Openness {
  std::vector<float> positive, negative;
};

// Line tracing, the definition itself (Yokoyama, Shirasawa & Pike 2002):
// for each azimuth the ray from a texel centre is walked in steps of 1/20
// cell over the bilinear surface through the texel centres, within
// `radiusM` (0: to the DEM's edge), keeping the largest and smallest
// elevation angles. NaN where some ray leaves the DEM at once.
Openness traceOpenness(const Heightfield& f, int azimuths, double radiusM) {
  Openness o;
  o.positive.assign(f.texelCount(), 0.0f);
  o.negative.assign(f.texelCount(), 0.0f);
  const double stepCells = 0.05;
  for (int row = 0; row < f.height; ++row) {
    for (int col = 0; col < f.width; ++col) {
      const double z = f.at(col, row);
      double highest = 0, lowest = 0;
      for (int a = 0; a < azimuths; ++a) {
        const double phi = 2 * kPi * a / azimuths;
        const double dc = std::cos(phi), dr = -std::sin(phi);  // rows grow south
        double hi = -std::numeric_limits<double>::infinity(), lo = -hi;
        for (int k = 1;; ++k) {
          const double d = k * stepCells, c = col + d * dc, r = row + d * dr;
          if (radiusM > 0 && d * kCellM > radiusM) break;
          if (c < 0 || r < 0 || c > f.width - 1 || r > f.height - 1) break;
          const double angle = std::atan((f.bilinearHeight(c, r) - z) / (d * kCellM));
          hi = std::max(hi, angle);
          lo = std::min(lo, angle);
        }
        highest += hi;  // -inf where the ray has no terrain: NaN below
        lowest += lo;
      }
      const double toDegrees = 180 / kPi;
      const size_t i = f.index(col, row);
      o.positive[i] = std::isfinite(highest) ? float(90 - toDegrees * highest / azimuths) : NAN;
      o.negative[i] = std::isfinite(lowest) ? float(90 + toDegrees * lowest / azimuths) : NAN;
    }
  }
  return o;
}

BakeOptions opennessOptions(int azimuths, double maxDistanceM) {
  BakeOptions o;
  o.azimuths = azimuths;
  o.maxDistanceM = maxDistanceM;
  o.positiveOpenness = o.negativeOpenness = true;
  return o;
}

bool onOuterRing(const Heightfield& f, size_t i) {
  const int col = int(i % f.width), row = int(i / f.width);
  return col == 0 || row == 0 || col == f.width - 1 || row == f.height - 1;
}

struct Difference {
  double mean = 0, max = 0;
};

// Over the texels inside the outer ring, which must all be finite.
Difference differenceInside(const Heightfield& f, const std::vector<float>& a,
                            const std::vector<float>& b) {
  Difference d;
  size_t n = 0;
  for (size_t i = 0; i < f.texelCount(); ++i) {
    if (onOuterRing(f, i)) continue;
    EXPECT_TRUE(std::isfinite(a[i]) && std::isfinite(b[i])) << i;
    const double e = std::abs(double(a[i]) - b[i]);
    d.mean += e;
    d.max = std::max(d.max, e);
    ++n;
  }
  d.mean /= double(n);
  return d;
}

// The sweep samples each line once per cell and blends the tangents of the
// two lines beside a texel (preprocess/horizon_sweep.h), where the tracing
// follows the bilinear surface continuously. Both agree where the horizon is
// far; on the pit's walls (slopes to 40°), with the horizon a cell or two
// away, one azimuth's angle differs by up to a few degrees, the mean of 9 to
// 16 azimuths by up to 1.1° (measured). Most texels are far closer: the mean
// difference over the DEM is 0.02°.
void expectTraced(int azimuths, double maxDistanceM, double maxDeg, double meanDeg) {
  const Heightfield field = bumpAndPit();
  const BakeResult r = bakeApertures(field, opennessOptions(azimuths, maxDistanceM));
  const Openness traced = traceOpenness(field, azimuths, maxDistanceM);
  const Difference pos = differenceInside(field, r.positiveOpenness, traced.positive);
  const Difference neg = differenceInside(field, r.negativeOpenness, traced.negative);
  EXPECT_LT(pos.mean, meanDeg);
  EXPECT_LT(neg.mean, meanDeg);
  EXPECT_LT(pos.max, maxDeg);
  EXPECT_LT(neg.max, maxDeg);
  // An open edge: the outer ring has azimuths with no terrain ahead.
  for (size_t i = 0; i < field.texelCount(); ++i) {
    if (!onOuterRing(field, i)) continue;
    ASSERT_TRUE(std::isnan(r.positiveOpenness[i]) && std::isnan(r.negativeOpenness[i])) << i;
    ASSERT_TRUE(std::isnan(traced.positive[i])) << i;
  }
}

TEST(Openness, MatchesLineTracingOverTheWholeDem) {
  expectTraced(16, 0.0, 1.5, 0.03);
}
TEST(Openness, MatchesLineTracingWithinAMaxDistance) {
  expectTraced(16, kTwelveCellsM, 1.5, 0.04);
}
TEST(Openness, MatchesLineTracingWithAnOddNumberOfAzimuths) {
  expectTraced(9, 0.0, 1.5, 0.03);
}

TEST(Openness, MatchesLineTracingOnTheScalarPath) {
  setHorizonAvx2Allowed(false);
  expectTraced(12, 0.0, 1.5, 0.03);
  setHorizonAvx2Allowed(true);
}

// Along the axes the lines pass through texel centres and the bilinear
// surface is linear between them, as the sweep's profile: the same angles,
// to float rounding and the fast arctangent (2e-6 rad).
TEST(Openness, EqualsLineTracingAlongTheAxes) {
  for (double maxDistanceM : {0.0, kTwelveCellsM}) {
    expectTraced(4, maxDistanceM, 2e-3, 1e-3);
  }
}

TEST(Openness, IsNinetyDegreesOnPlanes) {
  for (double slope : {0.0, 0.3}) {
    const Heightfield plane =
        test::makeField(32, 24, kCellM, [&](double x, double y) { return slope * (x - 0.5 * y); });
    for (double maxDistanceM : {0.0, 60.0}) {
      const BakeResult r = bakeApertures(plane, opennessOptions(16, maxDistanceM));
      for (size_t i = 0; i < plane.texelCount(); ++i) {
        if (onOuterRing(plane, i)) continue;
        // Uphill and downhill azimuths come in pairs of opposite angles.
        ASSERT_NEAR(r.positiveOpenness[i], 90.0f, 2e-3f) << i << " slope " << slope;
        ASSERT_NEAR(r.negativeOpenness[i], 90.0f, 2e-3f) << i << " slope " << slope;
      }
    }
  }
}

TEST(Openness, IsAboveNinetyOnAPeakAndBelowInAPit) {
  const Heightfield field = bumpAndPit();
  const BakeResult r = bakeApertures(field, opennessOptions(16, 0.0));
  // The bump's top at (-80, 60) m, the pit's bottom at (90, -70) m.
  const size_t peak = field.index(15, 17), pit = field.index(32, 30);
  EXPECT_GT(r.positiveOpenness[peak], 95.0f);
  EXPECT_LT(r.negativeOpenness[peak], 85.0f);
  EXPECT_LT(r.positiveOpenness[pit], 80.0f);
  EXPECT_GT(r.negativeOpenness[pit], 92.0f);
}

// Negative openness is the positive openness of the inverted DEM.
TEST(Openness, NegativeIsThePositiveOfTheInvertedDem) {
  Heightfield field = bumpAndPit();
  const BakeResult r = bakeApertures(field, opennessOptions(16, 0.0));
  for (float& z : field.z) z = -z;
  BakeOptions o = opennessOptions(16, 0.0);
  o.negativeOpenness = false;
  const BakeResult inverted = bakeApertures(field, o);
  for (size_t i = 0; i < field.texelCount(); ++i) {
    if (std::isnan(r.negativeOpenness[i])) {
      ASSERT_TRUE(std::isnan(inverted.positiveOpenness[i])) << i;
    } else {
      ASSERT_EQ(r.negativeOpenness[i], inverted.positiveOpenness[i]) << i;
    }
  }
}

// With clamped edges the terrain goes on flat beyond the edge: every azimuth
// has a horizon, and a plane's edge texels see 90° too.
TEST(Openness, ClampedEdgesGiveEveryTexelAValue) {
  const Heightfield plane = test::makeField(20, 20, kCellM, [](double, double) { return 5.0; });
  BakeOptions o = opennessOptions(16, 0.0);
  o.clampEdge = true;
  const BakeResult r = bakeApertures(plane, o);
  for (size_t i = 0; i < plane.texelCount(); ++i) {
    ASSERT_NEAR(r.positiveOpenness[i], 90.0f, 1e-3f) << i;
    ASSERT_NEAR(r.negativeOpenness[i], 90.0f, 1e-3f) << i;
  }
  const BakeResult bumpy = bakeApertures(bumpAndPit(), o);
  for (float v : bumpy.positiveOpenness) ASSERT_TRUE(std::isfinite(v));
  for (float v : bumpy.negativeOpenness) ASSERT_TRUE(std::isfinite(v));
}

TEST(Openness, RefusesWhatItCannotCompute) {
  const Heightfield field = bumpAndPit();
  BakeOptions rays = opennessOptions(16, 0.0);
  rays.method = BakeMethod::Rays;
  EXPECT_THROW(bakeApertures(field, rays), std::invalid_argument);
  BakeOptions curved = opennessOptions(16, 0.0);
  curved.curvature = true;
  EXPECT_THROW(bakeApertures(field, curved), std::invalid_argument);
  curved.negativeOpenness = false;  // the positive one is the sweep's own
  EXPECT_EQ(bakeApertures(field, curved).positiveOpenness.size(), field.texelCount());
}

// A tile baked within a max distance equals the same texels of the whole.
TEST(Openness, AWindowEqualsTheWholeDem) {
  const Heightfield field = bumpAndPit();
  const BakeOptions o = opennessOptions(16, 60.0);
  const BakeResult whole = bakeApertures(field, o);
  const TexelWindow window{.col = 10, .row = 20, .width = 16, .height = 12};
  const BakeResult tile = bakeApertureWindow(field, window, o);
  for (int row = 0; row < window.height; ++row) {
    for (int col = 0; col < window.width; ++col) {
      const size_t t = size_t(row) * window.width + col;
      const size_t i = field.index(window.col + col, window.row + row);
      ASSERT_EQ(tile.positiveOpenness[t], whole.positiveOpenness[i]) << col << "," << row;
      ASSERT_EQ(tile.negativeOpenness[t], whole.negativeOpenness[i]) << col << "," << row;
    }
  }
}

}  // namespace
}  // namespace aal
