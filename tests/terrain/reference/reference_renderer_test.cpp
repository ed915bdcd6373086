// The CPU reference renderer against closed forms: open ground, a conical
// pit's sky and shadow, and a whole image of a flat plane.
#include "reference_renderer.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

Heightfield field(int size, double cellM, double (*height)(double x, double y)) {
  Heightfield f;
  f.width = f.height = size;
  f.cellSizeXM = f.cellSizeYM = cellM;
  f.format = "test";
  f.z.resize(f.texelCount());
  for (int row = 0; row < size; ++row) {
    for (int col = 0; col < size; ++col) {
      const double x = (col - 0.5 * (size - 1)) * cellM, y = (0.5 * (size - 1) - row) * cellM;
      f.z[f.index(col, row)] = static_cast<float>(height(x, y));
    }
  }
  return f;
}

glm::vec3 sunAt(double elevationDeg, double azimuthDeg = 30) {
  const double e = elevationDeg * kPi / 180, a = azimuthDeg * kPi / 180;
  return glm::vec3(std::cos(e) * std::cos(a), std::cos(e) * std::sin(a), std::sin(e));
}

ReferenceSettings lighting(double sunElevationDeg) {
  ReferenceSettings s;
  s.lighting.sunDirection = sunAt(sunElevationDeg);
  s.lighting.sunIrradiance = glm::vec3(100.0f, 90.0f, 80.0f);
  s.lighting.skyRadiance = glm::vec3(2.0f, 3.0f, 5.0f);
  s.albedo = glm::vec3(0.3f);
  s.sunRays = 16;
  s.skyRays = 1024;
  return s;
}

double flat(double, double) {
  return 100.0;
}

TEST(ReferenceRenderer, OpenFlatGroundIsTheClosedForm) {
  const Heightfield f = field(33, 10, flat);
  const ReferenceSettings s = lighting(40);
  const glm::vec3 got = referenceRadianceAt(f, s, {12, -7, 100}, 1);
  const glm::vec3 expected = 0.3f / float(kPi) *
                             (s.lighting.sunIrradiance * std::sin(float(40 * kPi / 180)) +
                              float(kPi) * s.lighting.skyRadiance);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(got[c], expected[c], 1e-4 * expected[c]) << c;
}

// A trench along y: flat bottom 200 m wide, 30-degree walls up to the DEM's
// east and west edges (x = +-320 m), 10 km long so that it is infinite
// for what the bottom's centre sees. From there the horizon across is the
// wall top, at tan H = k (320 - 100) / 320 whatever the azimuth (in the
// x-z plane).
const double kWall = std::tan(30 * kPi / 180);
double trench(double x, double) {
  return kWall * std::max(0.0, std::abs(x) - 100.0);
}
Heightfield trenchField() {
  Heightfield f;
  f.width = 65;
  f.height = 1025;
  f.cellSizeXM = f.cellSizeYM = 10;
  f.format = "test";
  f.z.resize(f.texelCount());
  for (int row = 0; row < f.height; ++row) {
    for (int col = 0; col < f.width; ++col) {
      f.z[f.index(col, row)] = static_cast<float>(trench((col - 32) * 10.0, 0));
    }
  }
  return f;
}
const double kTrenchHorizon = std::atan(kWall * 220 / 320);

TEST(ReferenceRenderer, TrenchBottomSeesTheSkyAboveItsWallsAndTheirBounce) {
  // View factor of an infinitely long opening bounded by horizons H on both
  // sides: cos H (the 2D crossed-strings form). The other rays hit the walls,
  // whose normals lean by 30 degrees: each brings a/pi * pi L_sky (1 + cos 30)/2.
  const Heightfield f = trenchField();
  ReferenceSettings s = lighting(20);
  s.lighting.sunIrradiance = glm::vec3(0.0f);
  const double a = 0.3, skyShare = std::cos(kTrenchHorizon);
  const double wallSky = a * (1 + std::cos(30 * kPi / 180)) / 2;  // bounce per unit L_sky
  const glm::vec3 got = referenceRadianceAt(f, s, {0, 0, 0}, 7);
  for (int c = 0; c < 3; ++c) {
    const double expected = a * s.lighting.skyRadiance[c] * (skyShare + (1 - skyShare) * wallSky);
    EXPECT_NEAR(got[c], expected, 0.01 * expected) << c;
  }
}

TEST(ReferenceRenderer, TrenchBottomIsInShadowBelowTheWallTopAndLitAboveIt) {
  const Heightfield f = trenchField();
  const double horizonDeg = kTrenchHorizon * 180 / kPi;  // 21.6 degrees
  ReferenceSettings s = lighting(horizonDeg - 2);
  s.lighting.sunDirection = sunAt(horizonDeg - 2, 0);  // from the east, across the trench
  s.lighting.skyRadiance = glm::vec3(0.0f);
  s.interreflection = false;  // no sunlight from the walls: direct light only
  EXPECT_EQ(referenceRadianceAt(f, s, {0, 0, 0}, 3), glm::vec3(0.0f));
  s.lighting.sunDirection = sunAt(horizonDeg + 2, 0);
  const glm::vec3 lit = referenceRadianceAt(f, s, {0, 0, 0}, 3);
  const float expected = 0.3f / float(kPi) * 100.0f * std::sin(float((horizonDeg + 2) * kPi / 180));
  EXPECT_NEAR(lit.r, expected, 1e-3 * expected);
  // With inter-reflection the sunlit east wall lights the shadowed bottom.
  s.lighting.sunDirection = sunAt(horizonDeg - 2, 0);
  s.interreflection = true;
  EXPECT_GT(referenceRadianceAt(f, s, {0, 0, 0}, 3).r, 0.01f * expected);
}

TEST(ReferenceRenderer, ImageOfFlatGroundIsUniformWithoutHaze) {
  const Heightfield f = field(65, 10, flat);
  ReferenceSettings s = lighting(50);
  s.skyRays = 16;
  s.width = 24;
  s.height = 16;
  s.camera.position = {0, -200, 500};
  s.camera.lookAt = {0, 0, 100};
  s.camera.verticalFovDeg = 40;
  const ReferenceImage image = renderReference(f, s);
  const glm::vec3 expected = 0.3f / float(kPi) *
                             (s.lighting.sunIrradiance * std::sin(float(50 * kPi / 180)) +
                              float(kPi) * s.lighting.skyRadiance);
  int terrain = 0;
  for (size_t i = 0; i < image.radiance.size(); ++i) {
    if (!image.terrain[i]) continue;
    ++terrain;
    EXPECT_NEAR(image.radiance[i].g, expected.g, 1e-3 * expected.g) << i;
  }
  EXPECT_EQ(terrain, 24 * 16);  // the camera sees nothing but the ground
  // The same in the measure `aal-render --compare` reports.
  const std::vector<glm::vec3> closedForm(image.radiance.size(), expected);
  EXPECT_LT(relativeRmse(image.radiance, closedForm, image.terrain), 1e-3);
}

TEST(ReferenceRenderer, RelativeRmseAndInteriorMask) {
  const std::vector<glm::vec3> ref(4, glm::vec3(1.0f));
  std::vector<glm::vec3> test(4, glm::vec3(1.1f));
  EXPECT_NEAR(relativeRmse(test, ref, {1, 1, 1, 1}), 0.1, 1e-6);
  // Pixels outside the mask count for nothing.
  test[2] = glm::vec3(50.0f);
  EXPECT_NEAR(relativeRmse(test, ref, {1, 1, 0, 1}), 0.1, 1e-6);
  EXPECT_GT(relativeRmse(test, ref, {1, 1, 1, 1}), 10.0);
  std::vector<uint8_t> mask(25, 1);
  mask[0] = 0;
  const std::vector<uint8_t> inner = interiorMask(mask, 5, 5);
  EXPECT_EQ(inner[6], 1);  // (1, 1): all four neighbours are terrain
  EXPECT_EQ(inner[1], 0);  // border row
  mask[7] = 0;
  EXPECT_EQ(interiorMask(mask, 5, 5)[6], 0);  // a neighbour is sky
}

TEST(ReferenceRenderer, RefusesEmptyImagesAndNoRays) {
  const Heightfield f = field(9, 10, flat);
  ReferenceSettings s = lighting(40);
  EXPECT_THROW(renderReference(f, s), std::invalid_argument);
  s.width = s.height = 4;
  s.skyRays = 0;
  EXPECT_THROW(renderReference(f, s), std::invalid_argument);
}

}  // namespace
}  // namespace aal
