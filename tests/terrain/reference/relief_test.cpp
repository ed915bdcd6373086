// The shaded relief (terrain/reference/relief.h) against closed forms on planes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/reference/relief.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kSunRadiusDeg = 0.26656;

// A plane z = slope_east * x + slope_north * y (metres; x east, y north) on
// a grid of `cell` metres, row 0 north.
Heightfield plane(int size, double cell, double slopeEast, double slopeNorth) {
  Heightfield f;
  f.width = f.height = size;
  f.cellSizeXM = f.cellSizeYM = cell;
  f.z.resize(f.texelCount());
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      f.z[f.index(c, r)] =
          static_cast<float>(slopeEast * c * cell + slopeNorth * (size - 1 - r) * cell);
    }
  }
  return f;
}

// The aperture of an unoccluded plane: the hemisphere about its normal.
ApertureMap openAperture(const Heightfield& f, glm::dvec3 normal) {
  ApertureMap m;
  m.width = f.width;
  m.height = f.height;
  normal = glm::normalize(normal);
  for (size_t i = 0; i < f.texelCount(); ++i) {
    m.texels.insert(m.texels.end(),
                    {float(normal.x), float(normal.y), float(normal.z), float(kPi / 2)});
  }
  return m;
}

ReliefSettings sunAt(double azimuth, double elevation, float sky) {
  ReliefSettings s;
  s.sunAzimuthDeg = azimuth;
  s.sunElevationDeg = elevation;
  s.skyWeight = sky;
  s.sunRadiusDeg = kSunRadiusDeg;
  s.obscurance.radiusM = 50;
  return s;
}

// Flat ground under the full sky: (1 - k) sin e for the sun (its disk wholly
// visible, Lambert at its centre) plus k cos r_s for the sky (the sky's share
// outside the sun's cap: 1 - (1 - cos r_s) of the hemisphere).
TEST(Relief, FlatPlaneIsTheClosedForm) {
  const Heightfield f = plane(24, 10, 0, 0);
  const ApertureMap m = openAperture(f, {0, 0, 1});
  for (const double e : {5.0, 20.0, 45.0, 70.0, 89.0}) {
    for (const float k : {0.0f, 0.2f, 1.0f}) {
      for (const bool exact : {false, true}) {
        ReliefSettings s = sunAt(123, e, k);
        s.mode = exact ? ShadingMode::Exact : ShadingMode::Approx;
        const ReliefImage r = shadeRelief(f, m, s);
        const double expected = (1 - k) * std::sin(e * kDeg) + k * std::cos(kSunRadiusDeg * kDeg);
        ASSERT_EQ(r.value.size(), f.texelCount());
        for (size_t i = 0; i < r.value.size(); ++i) {
          ASSERT_NEAR(r.value[i], expected, 2e-6) << "e " << e << " k " << k << " texel " << i;
        }
      }
    }
  }
}

// A plane tilted by s facing west (rising east), sun from azimuth a at
// elevation e: cos of the angle between the normal and the sun by the
// spherical law of cosines, cos s sin e + sin s cos e cos(a - 270).
TEST(Relief, SlopedPlaneFacingTheSunIsTheCosineOfTheAngle) {
  for (const double slopeDeg : {10.0, 30.0, 50.0}) {
    const double t = std::tan(slopeDeg * kDeg);
    const Heightfield f = plane(16, 5, t, 0);
    const ApertureMap m = openAperture(f, {-t, 0, 1});
    for (const double a : {270.0, 250.0, 300.0}) {
      for (const double e : {15.0, 40.0}) {
        const ReliefImage r = shadeRelief(f, m, sunAt(a, e, 0.0f));
        const double expected =
            std::cos(slopeDeg * kDeg) * std::sin(e * kDeg) +
            std::sin(slopeDeg * kDeg) * std::cos(e * kDeg) * std::cos((a - 270) * kDeg);
        for (size_t i = 0; i < r.value.size(); ++i) {  // edges too: one-sided differences
          ASSERT_NEAR(r.value[i], expected, 2e-5) << slopeDeg << " " << a << " " << e << " " << i;
        }
      }
    }
  }
}

TEST(Relief, SkyOnlyIsOneOnOpenFlatGroundAndFollowsTheAperture) {
  const Heightfield f = plane(12, 10, 0, 0);
  ApertureMap m = openAperture(f, {0, 0, 1});
  ReliefSettings s;
  s.lighting = ReliefLighting::SkyOnly;
  s.obscurance.radiusM = 30;
  for (const float v : shadeRelief(f, m, s).value) ASSERT_NEAR(v, 1.0f, 1e-6f);
  // A narrower cap sees sin^2 r of the sky.
  for (size_t i = 0; i < f.texelCount(); ++i) m.texels[4 * i + 3] = 0.5f;
  for (const float v : shadeRelief(f, m, s).value) {
    ASSERT_NEAR(v, std::sin(0.5) * std::sin(0.5), 1e-6);
  }
}

// Sky-only relief ignores the sky weight, obscurances included (W darkens
// the creases of a bumpy DEM whatever k says).
TEST(Relief, SkyOnlyIgnoresTheSkyWeight) {
  Heightfield f = plane(24, 10, 0, 0);
  for (int r = 0; r < 24; ++r) {
    for (int c = 0; c < 24; ++c) f.z[f.index(c, r)] = 30.0f * float(std::abs(c - 12));  // a V
  }
  const ApertureMap m = openAperture(f, {0, 0, 1});
  ReliefSettings s;
  s.lighting = ReliefLighting::SkyOnly;
  s.obscurance.radiusM = 40;
  s.skyWeight = 0.2f;
  const ReliefImage a = shadeRelief(f, m, s);
  s.skyWeight = 0.0f;
  const ReliefImage b = shadeRelief(f, m, s);
  EXPECT_EQ(a.value, b.value);
  s.obscurance.enabled = false;
  const ReliefImage open = shadeRelief(f, m, s);
  EXPECT_LT(a.value[f.index(12, 12)], open.value[f.index(12, 12)] - 0.01);  // the crease
}

TEST(Relief, SunOutsideTheApertureCastsShadow) {
  const Heightfield f = plane(12, 10, 0, 0);
  ApertureMap m = openAperture(f, {0, 0, 1});
  for (size_t i = 0; i < f.texelCount(); ++i) m.texels[4 * i + 3] = 0.3f;  // deep pit
  const ReliefImage r = shadeRelief(f, m, sunAt(315, 45, 0.25f));
  // No sun; the sky through a cap of 0.3 rad, none of it taken by the sun.
  for (const float v : r.value) ASSERT_NEAR(v, 0.25 * std::sin(0.3) * std::sin(0.3), 1e-6);
}

TEST(Relief, VoidsAreNaNAndEverythingElseIsInRange) {
  Heightfield f = plane(10, 10, 0.3, -0.2);
  f.voidMask.assign(f.texelCount(), 0);
  f.voidMask[f.index(3, 4)] = 1;
  f.voidCount = 1;
  const ApertureMap m = openAperture(f, {-0.3, 0.2, 1});
  const ReliefImage r = shadeRelief(f, m, sunAt(315, 45, 0.2f));
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 10; ++x) {
      const size_t i = f.index(x, y);
      EXPECT_EQ(r.isVoid(i), x == 3 && y == 4) << x << " " << y;
      if (!r.isVoid(i)) {
        EXPECT_GE(r.value[i], 0.0f);
        EXPECT_LE(r.value[i], 1.0f);
      }
    }
  }
}

// gdaldem's weights cos^2(aspect - a) sum to 2 whatever the aspect and
// favour light along the fall line: a west-facing slope (aspect 270) is lit
// by the sun at 270 alone with weight 1, none from 360.
TEST(Relief, MultidirectionalWeights) {
  for (double aspect = 0; aspect < 360; aspect += 7.5) {
    const std::array<double, 4> w = multidirectionalWeights(aspect);
    EXPECT_NEAR(w[0] + w[1] + w[2] + w[3], 2.0, 1e-12) << aspect;
  }
  const std::array<double, 4> west = multidirectionalWeights(270);
  EXPECT_NEAR(west[1], 1.0, 1e-12);
  EXPECT_NEAR(west[3], 0.0, 1e-12);
  EXPECT_NEAR(west[0], 0.5, 1e-12);
  EXPECT_NEAR(west[2], 0.5, 1e-12);
  // gdaldem's own form: with the gradient (gx east, gy south), w270 =
  // gx^2 / (gx^2 + gy^2), w360 = gy^2 / (...), w225 = 0.5 - gx gy / (...).
  const double gx = 0.3, gy = -0.7, g2 = gx * gx + gy * gy;
  // The slope faces down the gradient: towards (-gx east, +gy north).
  const double aspect = std::atan2(-gx, gy) / kDeg;
  const std::array<double, 4> w = multidirectionalWeights(aspect);
  EXPECT_NEAR(w[0], 0.5 - gx * gy / g2, 1e-12);
  EXPECT_NEAR(w[1], gx * gx / g2, 1e-12);
  EXPECT_NEAR(w[2], 0.5 + gx * gy / g2, 1e-12);
  EXPECT_NEAR(w[3], gy * gy / g2, 1e-12);
  // On flat ground every sun gives sin e: the weighted mean is sin e too.
  const Heightfield f = plane(8, 10, 0, 0);
  ReliefSettings s = sunAt(0, 30, 0.0f);
  s.lighting = ReliefLighting::Multidirectional;
  for (const float v : shadeRelief(f, openAperture(f, {0, 0, 1}), s).value) {
    ASSERT_NEAR(v, 0.5, 2e-6);
  }
  // A west-facing 30 deg slope: (w225 cos t225 + w315 cos t315 + w360 cos t360) / 2.
  const double t = std::tan(30 * kDeg);
  const Heightfield g = plane(8, 10, t, 0);
  double expected = 0;
  for (size_t k = 0; k < 4; ++k) {
    const double a = kMultidirectionalAzimuthsDeg[k];
    const double c = std::cos(30 * kDeg) * std::sin(30 * kDeg) +
                     std::sin(30 * kDeg) * std::cos(30 * kDeg) * std::cos((a - 270) * kDeg);
    expected += west[k] * std::max(0.0, c) / 2;
  }
  for (const float v : shadeRelief(g, openAperture(g, {-t, 0, 1}), s).value) {
    ASSERT_NEAR(v, expected, 2e-5);
  }
}

TEST(Relief, WaterIsLitFlatOnlyWhereAsked) {
  const double t = std::tan(30 * kDeg);
  const Heightfield f = plane(10, 10, t, 0);  // heights 0 .. 9 * 10 * t east-wards
  const ApertureMap m = openAperture(f, {-t, 0, 1});
  ReliefSettings s = sunAt(270, 40, 0.0f);
  const ReliefImage dry = shadeRelief(f, m, s);
  EXPECT_TRUE(dry.water.empty());
  s.waterLevelM = 20.0;  // columns 0..3 (heights 0, 5.8, 11.5, 17.3)
  const ReliefImage wet = shadeRelief(f, m, s);
  ASSERT_EQ(wet.water.size(), f.texelCount());
  for (int y = 0; y < 10; ++y) {
    for (int x = 0; x < 10; ++x) {
      const size_t i = f.index(x, y);
      EXPECT_EQ(wet.water[i], x <= 3 ? 1 : 0) << x;
      if (x <= 3) {
        // A flat surface under the bent normal of the slope: sun at the
        // centroid, N = up: sin e.
        EXPECT_NEAR(wet.value[i], std::sin(40 * kDeg), 2e-5) << x;
      } else {
        EXPECT_EQ(wet.value[i], dry.value[i]) << x;
      }
    }
  }
}

TEST(Relief, ResampledOutputKeepsTheExtent) {
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.originX = 1000;
  geo.originY = 5000;
  geo.stepX = 30;
  geo.stepY = 20;
  const GeoReference half = resampledGeoReference(geo, 100, 60, 50, 30);
  EXPECT_DOUBLE_EQ(half.stepX, 60);
  EXPECT_DOUBLE_EQ(half.stepY, 40);
  EXPECT_DOUBLE_EQ(half.originX - half.stepX / 2, geo.originX - geo.stepX / 2);
  EXPECT_DOUBLE_EQ(half.originY + half.stepY / 2, geo.originY + geo.stepY / 2);
  // Two pixels per texel on a plane: the same value everywhere.
  const Heightfield f = plane(9, 10, 0.2, 0.1);
  ReliefSettings s = sunAt(200, 35, 0.0f);
  s.outWidth = 18;
  s.outHeight = 18;
  const ReliefImage r = shadeRelief(f, openAperture(f, {-0.2, -0.1, 1}), s);
  ASSERT_EQ(r.value.size(), 18u * 18u);
  const glm::dvec3 n = glm::normalize(glm::dvec3(-0.2, -0.1, 1));
  const double expected = std::max(0.0, glm::dot(n, glm::dvec3(sunDirection(200, 35))));
  for (const float v : r.value) ASSERT_NEAR(v, expected, 2e-5);
}

// At half the resolution a pixel is the mean of its 2 x 2 texels' values,
// not the value at its centre.
TEST(Relief, CoarserPixelsAverageTheirTexels) {
  Heightfield f = plane(16, 10, 0, 0);
  for (int r = 0; r < 16; ++r) {
    for (int c = 0; c < 16; ++c) f.z[f.index(c, r)] = 20.0f * float((c * 7 + r * 3) % 5);
  }
  ApertureMap m = openAperture(f, {0, 0, 1});
  for (size_t i = 0; i < f.texelCount(); ++i) m.texels[4 * i + 3] = 0.8f + 0.05f * float(i % 7);
  ReliefSettings s = sunAt(300, 35, 0.3f);
  s.obscurance.enabled = false;
  const ReliefImage full = shadeRelief(f, m, s);
  s.outWidth = s.outHeight = 8;
  const ReliefImage half = shadeRelief(f, m, s);
  double differs = 0;
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      double mean = 0;
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) mean += full.value[f.index(2 * x + dx, 2 * y + dy)] / 4;
      }
      const float v = half.value[static_cast<size_t>(y) * 8 + x];
      ASSERT_NEAR(v, mean, 1e-6) << x << " " << y;
      differs = std::max(differs, double(std::abs(v - full.value[f.index(2 * x, 2 * y)])));
    }
  }
  EXPECT_GT(differs, 0.05);  // the texels differ: a sample would not be the mean
}

// The tool holds the map as halves: the same relief as the floats when the
// values are halves already, and within their precision otherwise.
TEST(Relief, HalfMapsShadeAsTheirFloats) {
  Heightfield f = plane(12, 10, 0, 0);
  for (int r = 0; r < 12; ++r) {
    for (int c = 0; c < 12; ++c) f.z[f.index(c, r)] = 15.0f * float((c * 5 + r * 3) % 4);
  }
  ApertureMap m = openAperture(f, {0, 0, 1});
  for (size_t i = 0; i < f.texelCount(); ++i) {
    m.texels[4 * i + 0] = 0.25f * float(i % 3) - 0.25f;  // exact in halves
    m.texels[4 * i + 3] = 0.5f + 0.125f * float(i % 7);
  }
  const ReliefSettings s = sunAt(250, 30, 0.3f);
  const ReliefImage floats = shadeRelief(f, m, s);
  const HalfApertureMap halves = toHalfApertureMap(m);
  ASSERT_EQ(halves.texels.size(), m.texels.size());
  EXPECT_EQ(shadeRelief(f, halves, s).value, floats.value);
  for (size_t i = 0; i < f.texelCount(); ++i) m.texels[4 * i + 3] += 1e-3f * float(i % 5);
  const ReliefImage rounded = shadeRelief(f, toHalfApertureMap(m), s);
  const ReliefImage exact = shadeRelief(f, m, s);
  for (size_t i = 0; i < exact.value.size(); ++i) {
    ASSERT_NEAR(rounded.value[i], exact.value[i], 2e-3) << i;
  }
  HalfApertureMap small = halves;
  small.height = 11;
  EXPECT_THROW(shadeRelief(f, small, s), std::invalid_argument);
}

TEST(Relief, RefusesAMismatchedMap) {
  const Heightfield f = plane(8, 10, 0, 0);
  ApertureMap m = openAperture(f, {0, 0, 1});
  const ReliefSettings s = sunAt(250, 30, 0.3f);  // (ReliefSettings{} is refused for itself)
  ASSERT_NO_THROW(shadeRelief(f, m, s));
  m.width = 7;
  EXPECT_THROW(shadeRelief(f, m, s), std::invalid_argument);
}

// A DEM without all its heights (a window's worth, as a HeightWindow of
// terrain/height_window.h holds, or none: demGeometry) is not the DEM, even
// with every row.
TEST(Relief, RefusesAWindowOfTheDem) {
  const Heightfield whole = plane(8, 10, 0, 0);
  const ApertureMap m = openAperture(whole, {0, 0, 1});
  const ReliefSettings s = sunAt(250, 30, 0.3f);
  ASSERT_NO_THROW(shadeRelief(whole, m, s));
  Heightfield window = whole;
  window.z.resize(size_t(4) * size_t(window.height));
  EXPECT_THROW(shadeRelief(window, m, s), std::invalid_argument);
  EXPECT_THROW(shadeRelief(window, toHalfApertureMap(m), s), std::invalid_argument);
}

}  // namespace
}  // namespace aal
