// Several apertures per texel (bench/sector_apertures.h) against the
// single aperture and against rays marched through the heightfield.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include <glm/geometric.hpp>

#include "aperture/bench/sector_apertures.h"
#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/ray_bake.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/preprocess/bake_test_util.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

Heightfield rugged(int size) {
  SyntheticTerrainOptions s;
  s.width = s.height = size;
  s.cellSizeM = 30;
  s.amplitudeM = 800;
  s.featureSizeTexels = 24;
  return makeSyntheticTerrain(s);
}

double angleDeg(const glm::vec3& a, const glm::vec3& b) {
  return std::atan2(double(glm::length(glm::cross(a, b))), double(glm::dot(a, b))) * 180.0 / kPi;
}

TEST(SectorApertures, SectorOfAzimuthCutsTheCircleFromEast) {
  EXPECT_EQ(sectorOfAzimuth(0.0, 4), 0);
  EXPECT_EQ(sectorOfAzimuth(0.5 * kPi - 1e-9, 4), 0);
  EXPECT_EQ(sectorOfAzimuth(0.5 * kPi + 1e-9, 4), 1);
  EXPECT_EQ(sectorOfAzimuth(-1e-9, 4), 3);
  EXPECT_EQ(sectorOfAzimuth(2 * kPi + 0.1, 4), 0);
  EXPECT_EQ(sectorOfAzimuth(kPi + 0.1, 2), 1);
}

TEST(SectorApertures, RefusesSectorsThatDoNotDivideTheAzimuths) {
  const Heightfield field = rugged(8);
  BakeOptions o;
  o.azimuths = 64;
  EXPECT_THROW(bakeSectorApertures(field, o, 3), std::invalid_argument);
  EXPECT_THROW(bakeSectorApertures(field, o, 0), std::invalid_argument);
  EXPECT_THROW(bakeSectorApertures(field, o, 32), std::invalid_argument);
  o.method = BakeMethod::Rays;
  EXPECT_THROW(bakeSectorApertures(field, o, 4), std::invalid_argument);
}

// One sector is the whole sky: the single aperture of the bake; and the
// solid angles of four sectors add up to it.
TEST(SectorApertures, SectorsAddUpToTheSingleAperture) {
  const Heightfield field = rugged(32);
  BakeOptions o;
  o.azimuths = 64;
  const SectorApertures sectors = bakeSectorApertures(field, o, 1);
  const ApertureMap single = bakeApertures(field, o).aperture;
  const SectorApertures four = bakeSectorApertures(field, o, 4);
  double worstAngle = 0, worstRadius = 0, worstSum = 0;
  for (size_t i = 0; i < field.texelCount(); ++i) {
    const float* t = &single.texels[4 * i];
    worstAngle = std::max(worstAngle, angleDeg(sectors.apertures[i].centre, {t[0], t[1], t[2]}));
    worstRadius = std::max(worstRadius, std::abs(double(sectors.apertures[i].radiusRad) - t[3]));
    double sum = 0;
    for (int k = 0; k < 4; ++k) sum += four.visibleSolidAngle[four.slot(i, k)];
    worstSum = std::max(worstSum, std::abs(sum - 2 * kPi * (1 - std::cos(double(t[3])))));
  }
  EXPECT_LT(worstAngle, 0.01);
  EXPECT_LT(worstRadius, 1e-4);
  EXPECT_LT(worstSum, 1e-4);
}

// Each sector's visible and occluded solid angle and mean direction against
// rays marched through the heightfield (rayEscapes, the reference bake's
// march), uniform over the sector's part of the sphere. The rays' sampling
// error is below (4 pi / K) sqrt(p (1 - p) / n) = 0.01 sr here (stratified).
TEST(SectorApertures, EverySectorMatchesMarchedRays) {
  const Heightfield field = rugged(40);
  BakeOptions o;
  o.azimuths = 64;
  constexpr int kSectors = 4;
  const SectorApertures map = bakeSectorApertures(field, o, kSectors);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  const double zMax = *std::max_element(field.z.begin(), field.z.end());
  const double sectorArea = 4 * kPi / kSectors;
  constexpr int kAzimuthStrata = 64, kHeightStrata = 64;  // 4096 rays per sector
  double worstVisible = 0, worstOccluded = 0, worstAngle = 0;
  double sumVisible = 0, sumOccluded = 0, sumAngle = 0;
  int sectorsTested = 0, anglesTested = 0;
  for (const auto& [col, row] : {std::pair{20, 20}, {8, 30}, {31, 9}, {14, 12}, {27, 33}}) {
    const size_t i = field.index(col, row);
    const double sx = terrain.slopeEast(i), sy = terrain.slopeNorth(i);
    for (int k = 0; k < kSectors; ++k) {
      double visible = 0, occluded = 0;
      glm::dvec3 visibleSum(0.0), occludedSum(0.0);
      for (int a = 0; a < kAzimuthStrata; ++a) {
        for (int h = 0; h < kHeightStrata; ++h) {
          // Stratum centres, uniform in azimuth and in z (uniform solid angle).
          const double phi = (k + (a + 0.5) / kAzimuthStrata) * 2 * kPi / kSectors;
          const double z = -1 + 2 * (h + 0.5) / kHeightStrata;
          const double c = std::sqrt(1 - z * z);
          const double dir[3] = {c * std::cos(phi), c * std::sin(phi), z};
          const bool abovePlane = z > c * (sx * std::cos(phi) + sy * std::sin(phi));
          const bool escapes = abovePlane && rayEscapes(terrain, o, terrain.x(col, row),
                                                        terrain.y(row), field.z[i], dir, zMax);
          const glm::dvec3 d(dir[0], dir[1], dir[2]);
          if (escapes) {
            visible += 1;
            visibleSum += d;
          } else if (z > 0) {
            occluded += 1;
            occludedSum += d;
          }
        }
      }
      const double n = kAzimuthStrata * kHeightStrata;
      const double visibleSr = sectorArea * visible / n, occludedSr = sectorArea * occluded / n;
      const size_t s = map.slot(i, k);
      const double dVisible = std::abs(visibleSr - map.visibleSolidAngle[s]);
      const double dOccluded = std::abs(occludedSr - map.occludedSolidAngle[s]);
      worstVisible = std::max(worstVisible, dVisible);
      worstOccluded = std::max(worstOccluded, dOccluded);
      sumVisible += dVisible;
      sumOccluded += dOccluded;
      ++sectorsTested;
      // Oat's caps: centred on the mean direction, with the region's solid angle.
      EXPECT_NEAR(1 - std::cos(map.apertures[s].radiusRad), visibleSr / (2 * kPi), 0.01)
          << col << "," << row << " sector " << k;
      const auto addAngle = [&](const SectorCap& cap, const glm::dvec3& sum) {
        const double angle = angleDeg(cap.centre, glm::vec3(glm::normalize(sum)));
        worstAngle = std::max(worstAngle, angle);
        sumAngle += angle;
        ++anglesTested;
      };
      if (visible > 200) addAngle(map.apertures[s], visibleSum);
      if (occluded > 200) addAngle(map.antiApertures[s], occludedSum);
    }
  }
  std::printf(
      "sectors vs rays: |dOmega| visible mean %.4f worst %.4f sr, occluded mean %.4f worst "
      "%.4f sr; centres mean %.2f worst %.2f deg\n",
      sumVisible / sectorsTested, worstVisible, sumOccluded / sectorsTested, worstOccluded,
      sumAngle / anglesTested, worstAngle);
  // The sweep's horizons differ from the rays' by about this much on the
  // whole sky too (Bake.SweepMatchesRaysOnFbmTerrain: 1 % of 2 pi); a slice
  // given to the wrong sector moves 0.1 sr, half a slice 0.03 sr per sector.
  EXPECT_LT(sumVisible / sectorsTested, 0.015);
  EXPECT_LT(sumOccluded / sectorsTested, 0.015);
  EXPECT_LT(worstVisible, 0.06);
  EXPECT_LT(worstOccluded, 0.06);
  EXPECT_LT(sumAngle / anglesTested, 1.5);
  EXPECT_LT(worstAngle, 6.0);
}

// Flat open ground: no occluders, so the anti-apertures hide nothing; each
// sector aperture is the quarter hemisphere, a cap of radius acos(3/4)
// around a direction 35 degrees up, which misses a low sun at a sector's
// edge: the cap's shape, not the bake, is the limit (docs/comparison.md).
TEST(SectorApertures, FlatGroundHasNoOccludersAndQuarterCaps) {
  const Heightfield field = test::makeField(9, 9, 30, [](double, double) { return 100.0; });
  BakeOptions o;
  o.azimuths = 64;
  const SectorApertures map = bakeSectorApertures(field, o, 4);
  const size_t centre = field.index(4, 4);
  for (int k = 0; k < 4; ++k) {
    const SectorCap& cap = map.apertures[map.slot(centre, k)];
    EXPECT_NEAR(map.visibleSolidAngle[map.slot(centre, k)], kPi / 2, 1e-4);
    EXPECT_NEAR(cap.radiusRad, std::acos(0.75), 1e-4);
    // Quarter of the hemisphere around (k + 1/2) 90 degrees: elevation
    // atan((pi / 4) / (sqrt(2) pi / 4)) = atan(1 / sqrt 2) = 35.26 degrees.
    EXPECT_NEAR(std::asin(cap.centre.z) * 180 / kPi, 35.26, 0.05);
    EXPECT_NEAR(map.occludedSolidAngle[map.slot(centre, k)], 0.0, 1e-6);
  }
  const float elevation = 3 * float(kPi) / 180;
  const auto sunAt = [&](double phi) {
    return glm::vec3(std::cos(elevation) * std::cos(phi), std::cos(elevation) * std::sin(phi),
                     std::sin(elevation));
  };
  for (const auto lookup : {SectorLookup::Containing, SectorLookup::Blended, SectorLookup::Union}) {
    EXPECT_FLOAT_EQ(antiApertureSunFraction(map, centre, sunAt(0.3), 0.004653f, lookup), 1.0f);
  }
  // In the middle of a sector the low sun is inside its cap; at its edge
  // (45 degrees off the centre's azimuth) 51 degrees from the centre, outside.
  EXPECT_FLOAT_EQ(
      sectorApertureSunFraction(map, centre, sunAt(kPi / 4), 0.004653f, SectorLookup::Containing),
      1.0f);
  EXPECT_FLOAT_EQ(
      sectorApertureSunFraction(map, centre, sunAt(0.01), 0.004653f, SectorLookup::Containing),
      0.0f);
}

}  // namespace
}  // namespace aal
