// The CPU reference renderer against closed forms: open ground, a conical
// pit's sky and shadow, and a whole image of a flat plane.
#include "aperture/terrain/reference/reference_renderer.h"

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

// A ridge 80 m high along y, 80 m east of the shaded point, across the whole
// DEM (rows reach 640 m north and south). In azimuth phi (from east) the
// horizon is the ramp's highest point within the DEM: the ramp rises from 0
// at x = 70 m to 80 m at the ridge (x = 80 m), z/r = 8 (x - 70) cos(phi) / x
// grows with x, so the horizon is at the ridge or where the ray leaves the
// DEM. Cosine-weighted, the sky it hides is (1/pi) int sin^2(e(phi)) / 2 dphi.
double ridgeHiddenSkyShare() {
  const int steps = 200000;
  double sum = 0;
  for (int i = 0; i < steps; ++i) {
    const double phi = -kPi / 2 + (i + 0.5) * kPi / steps;
    const double x = std::min(80.0, 640.0 / std::max(std::abs(std::tan(phi)), 1e-12));
    if (x <= 70) continue;
    const double e = std::atan(8 * (x - 70) * std::cos(phi) / x);
    sum += std::sin(e) * std::sin(e) / 2;
  }
  return sum * (kPi / steps) / kPi;
}

TEST(ReferenceRenderer, OneWallHidesItsShareOfTheSkyWhateverTheRayCount) {
  Heightfield f = field(129, 10, flat);
  for (int row = 0; row < f.height; ++row) {
    for (int col = 0; col < f.width; ++col) f.z[f.index(col, row)] = col == 72 ? 80.0f : 0.0f;
  }
  ReferenceSettings s = lighting(40);
  s.lighting.sunIrradiance = glm::vec3(0.0f);
  s.interreflection = false;
  const double expected = 0.3 * s.lighting.skyRadiance.b * (1 - ridgeHiddenSkyShare());
  // Square counts and others: 128 once left the azimuths 300-360 degrees
  // around N (east of it, where the ridge is) unsampled, 5 % too bright.
  for (int rays : {64, 128, 100, 37, 200}) {
    s.skyRays = rays;
    double sum = 0;
    const int seeds = 64;
    for (int seed = 0; seed < seeds; ++seed) sum += referenceRadianceAt(f, s, {0, 0, 0}, seed).b;
    EXPECT_NEAR(sum / seeds, expected, 0.005 * expected) << rays << " rays";
  }
}

// Gentle waves under a high sun with a point-like disk, no sky: nothing is
// random, so a pixel of n x n subpixels is exactly the mean of the n x n
// pixels of an image n times as wide and high.
double waves(double x, double y) {
  return 20 * std::sin(x / 150) * std::cos(y / 170);
}

// A deterministic view of the waves: a point sun, no sky and no bounce, so
// that a pixel's value depends on where its rays meet the terrain alone.
ReferenceSettings pointSunView() {
  ReferenceSettings s = lighting(60);
  s.lighting.sunRadiusRad = 1e-6f;
  s.lighting.skyRadiance = glm::vec3(0.0f);
  s.interreflection = false;
  s.camera.position = {0, -200, 500};
  s.camera.lookAt = {0, 0, 0};
  s.camera.verticalFovDeg = 30;
  return s;
}

TEST(ReferenceFootprint, IsTheMeanOfPointSamplesOverThePixel) {
  const Heightfield f = field(65, 10, waves);
  ReferenceSettings s = pointSunView();
  s.width = 12;
  s.height = 8;
  s.subpixels = 2;
  const ReferenceImage pixels = renderReference(f, s);
  s.width = 24;
  s.height = 16;
  s.subpixels = 1;
  const ReferenceImage points = renderReference(f, s);
  int checked = 0, differFromTheCentre = 0;
  for (uint32_t y = 0; y < 8; ++y) {
    for (uint32_t x = 0; x < 12; ++x) {
      const size_t i = y * 12 + x;
      ASSERT_EQ(pixels.terrain[i], 1) << x << "," << y;
      glm::vec3 mean(0.0f);
      for (uint32_t j = 0; j < 4; ++j)
        mean += points.radiance[(2 * y + j / 2) * 24 + 2 * x + j % 2];
      mean /= 4.0f;
      EXPECT_NEAR(pixels.radiance[i].g, mean.g, 1e-5 * mean.g) << x << "," << y;
      ++checked;
      // The footprint matters: the mean is not the centre's value (which
      // lies between the four point samples).
      const float a = points.radiance[(2 * y) * 24 + 2 * x].g;
      const float d = points.radiance[(2 * y + 1) * 24 + 2 * x + 1].g;
      if (std::abs(a - d) > 1e-3f * mean.g) ++differFromTheCentre;
    }
  }
  EXPECT_EQ(checked, 96);
  EXPECT_GT(differFromTheCentre, 48);
}

TEST(ReferenceFootprint, OneSubpixelIsThePointThroughThePixelCentre) {
  // One subpixel is the ray through the pixel's centre: a 1 x 1 image and a
  // 3 x 3 image's middle pixel look along the same ray (in the deterministic
  // scene of the test above, so that seeds do not matter).
  const Heightfield f = field(65, 10, waves);
  ReferenceSettings s = pointSunView();
  s.width = s.height = 1;
  const ReferenceImage one = renderReference(f, s);
  s.width = s.height = 3;
  const ReferenceImage three = renderReference(f, s);
  ASSERT_EQ(one.terrain[0], 1);
  EXPECT_NEAR(one.radiance[0].g, three.radiance[4].g, 1e-5 * three.radiance[4].g);
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
  s.skyRays = 4;
  s.subpixels = 0;
  EXPECT_THROW(renderReference(f, s), std::invalid_argument);
  s.subpixels = kMaxReferenceSubpixels + 1;
  EXPECT_THROW(renderReference(f, s), std::invalid_argument);
  s.subpixels = kMaxReferenceSubpixels;
  EXPECT_NO_THROW(renderReference(f, s));
}

}  // namespace
}  // namespace aal
