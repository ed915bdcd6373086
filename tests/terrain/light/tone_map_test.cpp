// Exposure, Hable's filmic curve and sRGB encoding (terrain/light/tone_map.h).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/sky_model.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/light/tone_map.h"

namespace aal {
namespace {

TEST(FilmicCurve, RunsFromZeroToOneAtTheWhitePointAndIncreases) {
  EXPECT_EQ(filmicCurve(0.0f), 0.0f);
  EXPECT_EQ(filmicCurve(-1.0f), 0.0f);
  EXPECT_EQ(filmicCurve(float(AAL_FILMIC_W)), 1.0f);
  EXPECT_EQ(filmicCurve(2.0f * float(AAL_FILMIC_W)), 1.0f);
  EXPECT_EQ(filmicCurve(1e38f), 1.0f);
  // Hable's published form (x (A x + C B) + D E) / (x (A x + B) + D F) - E / F,
  // in double, over its value at W.
  auto published = [](double x) {
    const double a = AAL_FILMIC_A, b = AAL_FILMIC_B, c = AAL_FILMIC_C, d = AAL_FILMIC_D,
                 e = AAL_FILMIC_E, f = AAL_FILMIC_F;
    return (x * (a * x + c * b) + d * e) / (x * (a * x + b) + d * f) - e / f;
  };
  for (double x : {0.01, 0.18, 1.0, 2.0, 5.0, 11.0}) {
    EXPECT_NEAR(filmicCurve(float(x)), published(x) / published(AAL_FILMIC_W), 1e-6) << x;
  }
  float previous = -1.0f;
  for (float x = 0.0f; x < float(AAL_FILMIC_W); x += 0.01f) {
    const float y = filmicCurve(x);
    EXPECT_GT(y, previous) << x;
    previous = y;
  }
}

TEST(FilmicCurve, InverseRoundTrips) {
  for (float y = 0.0f; y < 0.995f; y += 0.005f) {
    EXPECT_NEAR(filmicCurve(inverseFilmicCurve(y)), y, 2e-6f) << y;
  }
  EXPECT_EQ(inverseFilmicCurve(0.0f), 0.0f);
  EXPECT_EQ(inverseFilmicCurve(-0.5f), 0.0f);
}

TEST(Srgb, MatchesTheStandardCurve) {
  EXPECT_EQ(linearToSrgb(0.0f), 0.0f);
  EXPECT_NEAR(linearToSrgb(1.0f), 1.0f, 1e-6f);
  EXPECT_NEAR(linearToSrgb(0.18f), 0.46135f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(0.5f), 0.73536f, 1e-5f);
  // Both pieces meet at the knee (0.0031308 -> 0.04045).
  EXPECT_NEAR(linearToSrgb(0.0031308f), 0.04045f, 1e-5f);
  EXPECT_NEAR(linearToSrgb(0.0031309f), 0.04045f, 1e-5f);
  EXPECT_EQ(linearToSrgb(2.0f), linearToSrgb(1.0f));
}

TEST(ToneMap, OutputStaysInTheUnitRange) {
  for (float v : {-5.0f, 0.0f, 1e-6f, 0.3f, 10.0f, 1e4f, 1e30f}) {
    const glm::vec3 out = toneMap(glm::vec3(v, 0.5f * v, 2.0f * v), 0.1f);
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(out[c], 0.0f) << v;
      EXPECT_LE(out[c], 1.0f) << v;
    }
  }
  const glm::vec3 white = toneMap(glm::vec3(1e6f), 1.0f);  // 1.055 - 0.055 in float
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(white[c], 1.0f, 1e-7f);
  EXPECT_EQ(toneMap(glm::vec3(0.0f), 1.0f), glm::vec3(0.0f));
}

TEST(Exposure, MiddleGreyLandsAtSrgbMiddleGrey) {
  for (float luminanceKcd : {0.01f, 1.0f, 7.0f, 300.0f}) {
    const float exposure = exposureForMiddleGrey(luminanceKcd);
    const glm::vec3 out = toneMap(glm::vec3(luminanceKcd), exposure);
    EXPECT_NEAR(out.g, linearToSrgb(kMiddleGrey), 1e-4f) << luminanceKcd;
  }
  EXPECT_TRUE(std::isfinite(exposureForMiddleGrey(0.0f)));
}

TEST(Exposure, Ev100FollowsTheSaturationBasedFormula) {
  // Sunny 16: EV100 = 15 -> L_max = 1.2 * 2^15 cd/m² = 39.3 kcd/m².
  EXPECT_NEAR(exposureFromEv100(15.0f), 1.0f / 39.3216f, 1e-6f);
  EXPECT_NEAR(exposureFromEv100(14.0f), 2.0f * exposureFromEv100(15.0f), 1e-7f);
}

TEST(AutoExposure, NoonTerrainIsMiddleGreyAndDuskIsDarker) {
  const double turbidity = 2.5, noonElevation = 60.0;
  auto lighting = [&](double elevation, glm::vec3& sun, glm::vec3& sky) {
    sun = sunIrradiance(elevation, turbidity);
    sky = averageSkyRadiance(makePreethamSky(sunDirection(180.0, elevation), turbidity));
  };
  glm::vec3 sun, sky;
  lighting(noonElevation, sun, sky);
  const float exposure = autoExposure(sun, noonElevation, sky);
  const float terrain = flatTerrainLuminance(sun, noonElevation, sky);
  // 0.2 / pi * (E_sun sin 60° + pi L_sky) by hand from the two luminances.
  const double expected =
      0.2 / std::numbers::pi *
      (luminance(sun) * std::sin(std::numbers::pi / 3) + std::numbers::pi * luminance(sky));
  EXPECT_NEAR(terrain, expected, 1e-4 * expected);
  const float grey = toneMap(glm::vec3(terrain), exposure).g;
  EXPECT_NEAR(grey, linearToSrgb(kMiddleGrey), 1e-4f);
  // Fresh snow (albedo 0.9) at noon is bright but not clipped.
  const float snow = toneMap(glm::vec3(terrain * 0.9f / 0.2f), exposure).g;
  EXPECT_GT(snow, 0.7f);
  EXPECT_LT(snow, 1.0f);
  // The same exposure at sunset and in the night.
  lighting(2.0, sun, sky);
  const float dusk = toneMap(glm::vec3(flatTerrainLuminance(sun, 2.0, sky)), exposure).g;
  lighting(-8.0, sun, sky);
  const float night = toneMap(glm::vec3(flatTerrainLuminance(sun, -8.0, sky)), exposure).g;
  EXPECT_LT(dusk, grey);
  EXPECT_EQ(night, 0.0f);
  std::printf(
      "autoExposure noon 60deg T=2.5: terrain %.3f kcd/m2, exposure %.4f; sRGB grey "
      "%.3f, snow %.3f, dusk(2deg) %.3f\n",
      terrain, exposure, grey, snow, dusk);
}

}  // namespace
}  // namespace aal
