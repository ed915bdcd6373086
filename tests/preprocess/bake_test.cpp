// aal-bake's numbers on scenes with known answers, and sweep vs rays.
#include "aperture/preprocess/bake.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/ray_bake.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/preprocess/bake_test_util.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;
using test::makeField;

const float* texel(const BakeResult& r, int col, int row) {
  return &r.aperture.texels[4 * (static_cast<size_t>(row) * r.aperture.width + col)];
}
double visibleFraction(const BakeResult& r, int col, int row) {
  return 1.0 - std::cos(texel(r, col, row)[3]);
}

BakeOptions sweepOptions(int azimuths = 64) {
  BakeOptions o;
  o.azimuths = azimuths;
  return o;
}
BakeOptions rayOptions(int rays) {
  BakeOptions o;
  o.method = BakeMethod::Rays;
  o.rays = rays;
  return o;
}

TEST(Bake, FlatPlaneSeesTheWholeHemisphere) {
  const Heightfield field = makeField(16, 12, 30.0, [](double, double) { return 100.0; });
  const float up[3] = {0, 0, 1};
  // The sweep is exact; the rays' bent normal carries their sampling noise.
  for (const auto& [o, maxAngleDeg] : {std::pair{sweepOptions(), 0.01}, {rayOptions(256), 1.5}}) {
    const BakeResult r = bakeApertures(field, o);
    for (int row = 0; row < field.height; ++row) {
      for (int col = 0; col < field.width; ++col) {
        const float* t = texel(r, col, row);
        EXPECT_NEAR(t[3], kPi / 2, 1e-4) << col << "," << row;  // Omega = 2 pi
        EXPECT_LT(test::angleBetweenDeg(t, up), maxAngleDeg) << col << "," << row;
      }
    }
  }
}

TEST(Bake, TiltedPlaneSeesTheHemisphereAroundItsNormal) {
  const double slope = 0.3;  // rising to the east
  const Heightfield field = makeField(33, 33, 10.0, [&](double x, double) { return slope * x; });
  const BakeResult r = bakeApertures(field, sweepOptions());
  const float n[3] = {float(-slope / std::sqrt(1 + slope * slope)), 0.0f,
                      float(1 / std::sqrt(1 + slope * slope))};
  for (int row = 1; row < field.height - 1; ++row) {
    for (int col = 1; col < field.width - 1; ++col) {
      EXPECT_NEAR(visibleFraction(r, col, row), 1.0, 1e-4) << col << "," << row;
      EXPECT_LT(test::angleBetweenDeg(texel(r, col, row), n), 0.05) << col << "," << row;
    }
  }
}

// Omega at the centre of the flat-bottomed pit, summed over the azimuths.
double flatPitOmega(double k, double r0, int size, double cellM, int azimuths) {
  double omega = 0;
  for (int a = 0; a < azimuths; ++a) {
    const double t = test::flatPitHorizonTan(k, r0, size, cellM, 2 * kPi * a / azimuths);
    omega += (2 * kPi / azimuths) * (1 - t / std::sqrt(1 + t * t));
  }
  return omega;
}

TEST(Bake, ConicalPitBottomSeesItsRim) {
  // A cone with a flat bottom (a cone's apex is not a cone on a grid: the
  // bilinear surface rises sqrt(2) times faster along the diagonals there).
  const double k = 0.6, r0 = 25.0;
  const int size = 65;
  const Heightfield field =
      makeField(size, size, 5.0, [&](double x, double y) { return test::flatPit(k, r0, x, y); });
  const BakeResult r = bakeApertures(field, sweepOptions(256));
  const double expected = flatPitOmega(k, r0, size, 5.0, 4096) / (2 * kPi);
  EXPECT_NEAR(visibleFraction(r, 32, 32), expected, 2e-3);
  EXPECT_NEAR(texel(r, 32, 32)[2], 1.0f, 1e-4);  // symmetric: the bent normal is the zenith
  // The brute-force rays agree within their sampling error on a smaller pit.
  const int small = 33;
  const Heightfield smallField =
      makeField(small, small, 5.0, [&](double x, double y) { return test::flatPit(k, r0, x, y); });
  const BakeResult rays = bakeApertures(smallField, rayOptions(4096));
  EXPECT_NEAR(visibleFraction(rays, 16, 16), flatPitOmega(k, r0, small, 5.0, 4096) / (2 * kPi),
              5e-3);
}

TEST(Bake, VValleyBottomMatchesTheClosedForm) {
  // z = k |x|: looking in azimuth phi from the valley floor the walls rise at
  // slope k |cos phi|, so Omega = sum dphi (1 - sin atan(k |cos phi|)).
  const double k = 0.8;
  const int azimuths = 64;
  const Heightfield field =
      makeField(65, 41, 10.0, [&](double x, double) { return k * std::abs(x); });
  const BakeResult r = bakeApertures(field, sweepOptions(azimuths));
  double omega = 0;
  for (int a = 0; a < azimuths; ++a) {
    const double slope = k * std::abs(std::cos(2 * kPi * a / azimuths));
    omega += (2 * kPi / azimuths) * (1 - slope / std::sqrt(1 + slope * slope));
  }
  for (int row = 15; row <= 25; ++row) {
    EXPECT_NEAR(visibleFraction(r, 32, row), omega / (2 * kPi), 1e-3) << row;
    const float* t = texel(r, 32, row);
    EXPECT_NEAR(t[0], 0.0f, 1e-5);  // symmetric: the bent normal stays vertical
    EXPECT_NEAR(t[2], 1.0f, 1e-4);
  }
}

TEST(Bake, IsolatedTowerShadowsItsNeighboursSky) {
  const Heightfield field = makeField(41, 41, 10.0, [](double x, double y) {
    return (std::abs(x) <= 10 && std::abs(y) <= 10) ? 200.0 : 0.0;
  });
  const BakeResult sweep = bakeApertures(field, sweepOptions(256));
  const BakeResult rays = bakeApertures(field, rayOptions(2048));
  // Ten cells east and west of the tower: bent normals lean away from it.
  EXPECT_GT(texel(sweep, 30, 20)[0], 0.02f);
  EXPECT_LT(texel(sweep, 10, 20)[0], -0.02f);
  // The tower (30 m wide, 200 m tall, 100 m away) hides roughly
  // width/distance * sin(elevation) = 0.3 * 0.89 sr of the sky.
  const double expectedLoss = 0.3 * std::sin(std::atan(200.0 / 100.0)) / (2 * kPi);
  EXPECT_NEAR(1 - visibleFraction(sweep, 30, 20), expectedLoss, 0.4 * expectedLoss);
  EXPECT_NEAR(visibleFraction(sweep, 30, 20), visibleFraction(rays, 30, 20), 0.01);
  // A far corner loses less of its sky than the close neighbours.
  EXPECT_GT(visibleFraction(sweep, 0, 0), visibleFraction(sweep, 30, 20));
  EXPECT_LT(visibleFraction(sweep, 0, 0), 1.0);
}

TEST(Bake, ClampedEdgeExtendsTheTerrainFlat) {
  // A plane rising east: open edges see the whole tilted hemisphere; with
  // clamped edges the ground beyond the west edge stays at the edge height,
  // so the western horizon is the horizontal: Omega loses sum over the
  // western azimuths of dphi * sin(atan(slope |cos phi|)).
  const double slope = 0.2;
  const int azimuths = 64;
  const Heightfield field = makeField(33, 33, 10.0, [&](double x, double) { return slope * x; });
  BakeOptions o = sweepOptions(azimuths);
  o.clampEdge = true;
  const BakeResult r = bakeApertures(field, o);
  double omega = 0;
  for (int a = 0; a < azimuths; ++a) {
    const double t = std::max(0.0, slope * std::cos(2 * kPi * a / azimuths));
    omega += (2 * kPi / azimuths) * (1 - t / std::sqrt(1 + t * t));
  }
  EXPECT_NEAR(visibleFraction(r, 16, 16), omega / (2 * kPi), 1e-4);
  EXPECT_LT(omega / (2 * kPi), 0.99);
}

TEST(Bake, CurvatureLowersDistantHorizons) {
  // A 400 m ridge (the east edge column) 60 km east of the plain's centre
  // texel; the Earth's curvature with refraction k = 0.13 drops it by
  // (1 - k) t^2 / (2 R) = 0.87 * 60000^2 / (2 * 6371 km) = 245.8 m.
  const Heightfield field =
      makeField(121, 5, 1000.0, [](double x, double) { return x > 59500 ? 400.0 : 0.0; });
  // Four azimuths: only the east slice, a quarter of the turn, meets the
  // ridge (the north and south ones leave the 5-row field first), and it
  // loses dPhi sin(theta) of the visible solid angle (preprocess/sky_slice.h):
  // visible fraction 1 - sin(theta) / 4. (With 64 slices the ridge's share
  // is too small for the float aperture to pin the drop within a metre.)
  BakeOptions flat = sweepOptions(4);
  BakeOptions curved = flat;
  curved.curvature = true;
  const BakeResult a = bakeApertures(field, flat);
  const BakeResult b = bakeApertures(field, curved);
  EXPECT_GT(visibleFraction(b, 60, 2), visibleFraction(a, 60, 2));
  const auto horizonHeightM = [](double visible) {
    const double sinTheta = 4 * (1 - visible);
    return 60000 * sinTheta / std::sqrt(1 - sinTheta * sinTheta);
  };
  const double drop = 0.87 * 60000.0 * 60000.0 / (2 * kEarthRadiusM);
  const double flatM = horizonHeightM(visibleFraction(a, 60, 2));
  const double curvedM = horizonHeightM(visibleFraction(b, 60, 2));
  std::printf("ridge seen %.3f m high flat, %.3f m curved (drop %.3f m)\n", flatM, curvedM, drop);
  EXPECT_NEAR(flatM, 400, 0.5);
  EXPECT_NEAR(curvedM, 400 - drop, 0.5);  // (1 + k) would drop it by 319.3 m
  // The reference method's rays graze the same curved ridge top: from the
  // centre texel, east, 2 m below it they are blocked, 2 m above they escape.
  const BakeTerrain terrain = prepareBakeTerrain(field);
  for (const double metres : {-2.0, 2.0}) {
    const double rise = (400 - drop + metres) / 60000;
    const double dir[3] = {1 / std::sqrt(1 + rise * rise), 0, rise / std::sqrt(1 + rise * rise)};
    EXPECT_EQ(rayEscapes(terrain, curved, 0, 0, 0, dir, 400), metres > 0) << metres << " m";
  }
}

SyntheticTerrainOptions fbm(int size, uint64_t seed = 7) {
  SyntheticTerrainOptions s;
  s.width = size;
  s.height = size;
  s.cellSizeM = 30;
  s.amplitudeM = 500;
  s.featureSizeTexels = 16;
  s.seed = seed;
  return s;
}

TEST(Bake, SweepMatchesRaysOnFbmTerrain) {
  // 1.4 km square of hills up to 200 m high with detail down to the texel.
  SyntheticTerrainOptions s = fbm(48);
  s.amplitudeM = 200;
  s.octaves = 5;
  const Heightfield field = makeSyntheticTerrain(s);
  const BakeResult sweep = bakeApertures(field, sweepOptions(64));
  const BakeResult rays = bakeApertures(field, rayOptions(2048));
  double sumOmega = 0, sumAngle = 0, maxOmega = 0;
  for (int row = 0; row < field.height; ++row) {
    for (int col = 0; col < field.width; ++col) {
      const double dOmega =
          std::abs(visibleFraction(sweep, col, row) - visibleFraction(rays, col, row));
      sumOmega += dOmega;
      maxOmega = std::max(maxOmega, dOmega);
      sumAngle += test::angleBetweenDeg(texel(sweep, col, row), texel(rays, col, row));
    }
  }
  const double n = static_cast<double>(field.texelCount());
  std::printf(
      "sweep vs rays on %dx%d fBm: mean |dOmega/2pi| %.5f (max %.4f), mean bent-normal "
      "angle %.3f deg\n",
      field.width, field.height, sumOmega / n, maxOmega, sumAngle / n);
  EXPECT_LE(sumOmega / n, 0.005);
  EXPECT_LE(sumAngle / n, 1.0);
}

// Rotating the DEM by 90 degrees counter-clockwise rotates the outputs.
TEST(Bake, RotatingTheDemRotatesTheApertures) {
  const Heightfield field = makeSyntheticTerrain(fbm(31, 3));
  Heightfield rotated = field;
  const int n = field.width;
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col)
      rotated.z[rotated.index(row, n - 1 - col)] = field.at(col, row);
  }
  const BakeResult a = bakeApertures(field, sweepOptions(64));
  const BakeResult b = bakeApertures(rotated, sweepOptions(64));
  double worst = 0;
  for (int row = 0; row < n; ++row) {
    for (int col = 0; col < n; ++col) {
      const float* ta = texel(a, col, row);
      const float* tb = texel(b, row, n - 1 - col);
      const float turned[3] = {-ta[1], ta[0], ta[2]};  // (x, y) -> (-y, x)
      worst = std::max(worst, test::angleBetweenDeg(turned, tb));
      EXPECT_NEAR(ta[3], tb[3], 1e-4) << col << "," << row;
    }
  }
  EXPECT_LT(worst, 0.01);
}

// A DEM 128 texels wide is swept with its sums' rows 132 apart
// (sumsPitch) and packed to 128 after; turned by 90 degrees it is 72 wide,
// swept at its own width. The apertures and every per-texel raster turn
// with it.
TEST(Bake, SumsSweptAtAPaddedPitchArePackedToTheWidth) {
  EXPECT_EQ(sumsPitch(128), 132);
  EXPECT_EQ(sumsPitch(72), 72);
  // Consecutive rows of 16-byte sums in different cache sets: a pitch of
  // an odd number of 64-byte lines.
  EXPECT_EQ(sumsPitch(4096) / 4 % 2, 1);
  SyntheticTerrainOptions s = fbm(128, 7);
  s.height = 72;
  const Heightfield field = makeSyntheticTerrain(s);
  ASSERT_EQ(field.width, 128);
  ASSERT_EQ(field.height, 72);
  Heightfield turned = field;
  turned.width = field.height;
  turned.height = field.width;
  for (int row = 0; row < field.height; ++row) {
    for (int col = 0; col < field.width; ++col) {
      turned.z[turned.index(row, field.width - 1 - col)] = field.at(col, row);
    }
  }
  // Unlimited (the block sweep), within a distance it scans (its window
  // sweep), and within one too long to scan (the line sweep's runs, placed
  // in the sums at the pitch).
  for (const double maxDistanceM : {0.0, 900.0, 16000.0}) {
    ASSERT_EQ(detail::scansWithinLimit(prepareBakeTerrain(field), {false, 0.0, maxDistanceM}),
              maxDistanceM == 900.0);
    BakeOptions o = sweepOptions(64);
    o.maxDistanceM = maxDistanceM;
    o.skyViewFactor = o.positiveOpenness = o.skyIllumination = true;
    const BakeResult a = bakeApertures(field, o);
    const BakeResult b = bakeApertures(turned, o);
    // Within a distance the sweep is not quite the same turned (3e-4 of
    // arc length and 0.08 degrees of bent normal at worst, at the width's
    // own pitch as well); rows packed wrong, or runs placed a row's width
    // apart instead of the pitch, miss by 0.04-0.08 of arc length.
    const double tolerance = maxDistanceM > 0.0 ? 1e-3 : 1e-4;
    const double toleranceDeg = maxDistanceM > 0.0 ? 0.2 : 0.01;
    ASSERT_EQ(a.aperture.texels.size(), 4 * field.texelCount());
    ASSERT_EQ(a.skyViewFactor.size(), field.texelCount());
    double worst = 0;
    for (int row = 0; row < field.height; ++row) {
      for (int col = 0; col < field.width; ++col) {
        const float* ta = texel(a, col, row);
        const float* tb = texel(b, row, field.width - 1 - col);
        const float rotated[3] = {-ta[1], ta[0], ta[2]};  // (x, y) -> (-y, x)
        worst = std::max(worst, test::angleBetweenDeg(rotated, tb));
        ASSERT_NEAR(ta[3], tb[3], tolerance) << col << "," << row;
        const size_t i = field.index(col, row), j = turned.index(row, field.width - 1 - col);
        ASSERT_NEAR(a.skyViewFactor[i], b.skyViewFactor[j], tolerance) << col << "," << row;
        // NaN on the outer ring (open edges: docs/baking.md).
        ASSERT_EQ(std::isnan(a.positiveOpenness[i]), std::isnan(b.positiveOpenness[j]));
        if (!std::isnan(a.positiveOpenness[i])) {
          ASSERT_NEAR(a.positiveOpenness[i], b.positiveOpenness[j], 100 * tolerance)
              << col << "," << row;
        }
        ASSERT_NEAR(a.skyIllumination[i], b.skyIllumination[j], tolerance) << col << "," << row;
      }
    }
    EXPECT_LT(worst, toleranceDeg) << maxDistanceM;
  }
}

TEST(Bake, ScalingXYAndZTogetherLeavesTheSkyUnchanged) {
  Heightfield field = makeSyntheticTerrain(fbm(24, 5));
  Heightfield scaled = field;
  scaled.cellSizeXM = scaled.cellSizeYM = 3 * field.cellSizeXM;
  for (float& z : scaled.z) z *= 3;
  const BakeResult a = bakeApertures(field, sweepOptions(32));
  const BakeResult b = bakeApertures(scaled, sweepOptions(32));
  for (size_t i = 0; i < a.aperture.texels.size(); ++i) {
    ASSERT_NEAR(a.aperture.texels[i], b.aperture.texels[i], 2e-5) << i;
  }
}

TEST(Bake, MoreAzimuthsConverge) {
  const Heightfield field = makeSyntheticTerrain(fbm(32, 11));
  const BakeResult reference = bakeApertures(field, sweepOptions(1024));
  double previous = 1e9;
  for (int azimuths : {8, 32, 128}) {
    const BakeResult r = bakeApertures(field, sweepOptions(azimuths));
    double error = 0;
    for (size_t i = 0; i < field.texelCount(); ++i) {
      error += std::abs(r.aperture.texels[4 * i + 3] - reference.aperture.texels[4 * i + 3]);
    }
    error /= field.texelCount();
    EXPECT_LT(error, previous) << azimuths << " azimuths";
    previous = error;
  }
  EXPECT_LT(previous, 2e-3);
}

TEST(Bake, SkyViewFactorOfAPitBottom) {
  // SVF = 1 - mean over azimuths of sin(horizon).
  const double k = 0.5, r0 = 30.0;
  const int size = 41;
  const Heightfield field =
      makeField(size, size, 10.0, [&](double x, double y) { return test::flatPit(k, r0, x, y); });
  BakeOptions o = sweepOptions(128);
  o.skyViewFactor = true;
  const BakeResult r = bakeApertures(field, o);
  double meanSin = 0;
  for (int a = 0; a < 4096; ++a) {
    const double t = test::flatPitHorizonTan(k, r0, size, 10.0, 2 * kPi * a / 4096);
    meanSin += t / std::sqrt(1 + t * t) / 4096;
  }
  ASSERT_EQ(r.skyViewFactor.size(), field.texelCount());
  EXPECT_NEAR(r.skyViewFactor[field.index(20, 20)], 1 - meanSin, 2e-3);
  for (float v : r.skyViewFactor) {
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
  }
}

TEST(Bake, NoNanAnywhereOnRoughTerrain) {
  SyntheticTerrainOptions s = fbm(48, 13);
  s.ridged = true;
  s.amplitudeM = 3000;
  const Heightfield field = makeSyntheticTerrain(s);
  BakeOptions o = sweepOptions(16);
  o.skyViewFactor = true;
  const BakeResult r = bakeApertures(field, o);
  for (float v : r.aperture.texels) ASSERT_TRUE(std::isfinite(v));
  for (float v : r.skyViewFactor) ASSERT_TRUE(std::isfinite(v));
}

TEST(Bake, RejectsOptionsOutOfRange) {
  const Heightfield field = makeField(8, 8, 1.0, [](double, double) { return 0.0; });
  BakeOptions o;
  o.azimuths = 3;
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
  o.azimuths = 100000;
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
  o = BakeOptions{};
  o.maxDistanceM = -1;
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
}

TEST(Bake, CancelStopsTheBake) {
  const Heightfield field = makeSyntheticTerrain(fbm(32));
  std::atomic<bool> cancel{true};
  BakeOptions o;
  o.cancel = &cancel;
  EXPECT_THROW(bakeApertures(field, o), BakeCancelled);
}

}  // namespace
}  // namespace aal
