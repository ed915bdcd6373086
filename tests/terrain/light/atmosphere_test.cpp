// Sunlight through the atmosphere (terrain/light/atmosphere.h): air mass, optical
// depths, the colour and strength of the direct beam, and its fade at sunset.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "aperture/terrain/light/atmosphere.h"

namespace aal {
namespace {

TEST(AirMass, KastenYoungMatchesItsTable) {
  // Kasten & Young 1989: 1.000 at the zenith (0.9997 for the formula), 1.995
  // at 60° zenith angle (secant 2), 37.92 at the horizon.
  EXPECT_NEAR(relativeAirMass(90.0), 1.0, 5e-4);
  EXPECT_NEAR(relativeAirMass(30.0), 1.9943, 1e-3);
  EXPECT_NEAR(relativeAirMass(0.0), 37.92, 0.05);
  // Close to the secant while the sun is high.
  for (double e = 20; e <= 90; e += 5) {
    EXPECT_NEAR(relativeAirMass(e), 1.0 / std::sin(e * std::numbers::pi / 180),
                0.01 / std::sin(e * std::numbers::pi / 180));
  }
}

TEST(AirMass, DecreasesWithElevationAndClampsOutsideRange) {
  for (double e = 0; e < 90; e += 0.5) EXPECT_GT(relativeAirMass(e), relativeAirMass(e + 0.5));
  EXPECT_DOUBLE_EQ(relativeAirMass(-3.0), relativeAirMass(0.0));
  EXPECT_DOUBLE_EQ(relativeAirMass(95.0), relativeAirMass(90.0));
}

TEST(OpticalDepth, RayleighDominatesInClearAirAndMatchesSeaLevelValues) {
  // T = 1 makes beta ~ 0; without ozone only Rayleigh is left. Sea-level
  // Rayleigh optical depths (Bucholtz 1995): ~0.045 at 680, ~0.097 at 550,
  // ~0.24 at 440 nm; Leckner's power law is within 6%.
  const glm::vec3 tau = verticalOpticalDepth(1.0, 0.0);
  EXPECT_NEAR(tau.r, 0.0446, 0.06 * 0.0446);
  EXPECT_NEAR(tau.g, 0.0973, 0.06 * 0.0973);
  EXPECT_NEAR(tau.b, 0.2450, 0.06 * 0.2450);
  // Ozone absorbs most at 550 nm (Chappuis band), least at 440 nm.
  const glm::vec3 ozone = verticalOpticalDepth(1.0, 0.35) - tau;
  EXPECT_NEAR(ozone.g, 0.0329, 1e-4);
  EXPECT_GT(ozone.g, ozone.r);
  EXPECT_GT(ozone.r, ozone.b);
  // Haze adds optical depth (Angstrom beta = 0.04608 T - 0.04586).
  EXPECT_NEAR(angstromBeta(2.5), 0.06934, 1e-5);
  EXPECT_DOUBLE_EQ(angstromBeta(0.5), 0.0);
  const glm::vec3 hazy = verticalOpticalDepth(6.0), clear = verticalOpticalDepth(2.0);
  for (int c = 0; c < 3; ++c) EXPECT_GT(hazy[c], clear[c]);
}

TEST(SunIrradiance, ClearNoonIsAboutOneHundredKiloluxAndNearWhite) {
  const glm::vec3 zenith = sunIrradiance(90.0, 2.5);
  const float y = luminance(zenith);
  EXPECT_GT(y, 95.0f);
  EXPECT_LT(y, 110.0f);
  // Slightly warm like real direct sunlight, but every channel within 20% of Y.
  for (int c = 0; c < 3; ++c) {
    EXPECT_GT(zenith[c], 0.8f * y) << c;
    EXPECT_LT(zenith[c], 1.2f * y) << c;
  }
  EXPECT_GT(zenith.r, zenith.g);
  EXPECT_GT(zenith.g, zenith.b);
  const float at60 = luminance(sunIrradiance(60.0, 2.5));
  EXPECT_GT(at60, 85.0f);
  EXPECT_LT(at60, 105.0f);
  std::printf("E_sun T=2.5: 90deg (%.2f %.2f %.2f) Y=%.2f klx; 60deg Y=%.2f klx\n", zenith.r,
              zenith.g, zenith.b, y, at60);
}

TEST(SunIrradiance, SunsetIsWarm) {
  for (double e : {2.0, 5.0}) {
    const glm::vec3 sun = sunIrradiance(e, 2.5);
    EXPECT_GT(sun.r, sun.g) << e;
    EXPECT_GT(sun.g, sun.b) << e;
  }
  const glm::vec3 low = sunIrradiance(2.0, 2.5);
  EXPECT_GT(low.r, 3.0f * low.g);
  const glm::vec3 s30 = sunIrradiance(30.0, 2.5), s5 = sunIrradiance(5.0, 2.5);
  std::printf("E_sun T=2.5: 30deg (%.3f %.3f %.3f) 5deg (%.3f %.3f %.3f) 2deg (%.3f %.3f %.4f)\n",
              s30.r, s30.g, s30.b, s5.r, s5.g, s5.b, low.r, low.g, low.b);
}

TEST(SunIrradiance, FadesOverTheDiskAndIsZeroBelowTheHorizon) {
  const double r = kSunAngularRadiusDeg;
  EXPECT_EQ(sunIrradiance(-r - 1e-9, 2.5), glm::vec3(0.0f));
  EXPECT_EQ(sunIrradiance(-5.0, 2.5), glm::vec3(0.0f));
  EXPECT_EQ(sunIrradiance(-90.0, 2.5), glm::vec3(0.0f));
  // Centre on the horizon: half the disk, same air mass as just above it.
  const glm::vec3 half = sunIrradiance(0.0, 2.5);
  const glm::vec3 full =
      static_cast<float>(kSolarIlluminanceKlx) * directTransmittance(relativeAirMass(0.0), 2.5);
  EXPECT_NEAR(half.r, 0.5f * full.r, 1e-4f * full.r);
  // Rises monotonically from first light to noon, without jumps.
  float previous = 0.0f;
  for (double e = -r; e <= 90.0; e += 0.01) {
    const float y = luminance(sunIrradiance(e, 2.5));
    EXPECT_GE(y, previous) << e;
    EXPECT_LT(y - previous, 0.1f) << e;
    previous = y;
  }
}

TEST(SunDisk, VisibleFractionIsTheCircularSegment) {
  const double r = kSunAngularRadiusDeg;
  EXPECT_DOUBLE_EQ(sunDiskVisibleFraction(r, r), 1.0);
  EXPECT_DOUBLE_EQ(sunDiskVisibleFraction(10.0, r), 1.0);
  EXPECT_NEAR(sunDiskVisibleFraction(0.0, r), 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(sunDiskVisibleFraction(-r, r), 0.0);
  for (double h = 0.05; h < 1.0; h += 0.05) {  // complementary halves
    EXPECT_NEAR(sunDiskVisibleFraction(h * r, r) + sunDiskVisibleFraction(-h * r, r), 1.0, 1e-12);
  }
  // Centre half a radius up: segment area (2pi/3 + sqrt(3)/4) / pi = 0.8045.
  EXPECT_NEAR(sunDiskVisibleFraction(0.5 * r, r), 0.80450, 1e-5);
  EXPECT_DOUBLE_EQ(sunDiskVisibleFraction(0.1, 0.0), 1.0);  // point sun
}

TEST(SunIrradiance, FollowsInverseSquareDistanceAndTurbidity) {
  const glm::vec3 at1 = sunIrradiance(45.0, 2.5, 1.0),
                  perihelion = sunIrradiance(45.0, 2.5, 0.9833);
  EXPECT_NEAR(perihelion.g / at1.g, 1.0 / (0.9833 * 0.9833), 1e-5);
  const glm::vec3 clear = sunIrradiance(20.0, 2.0), hazy = sunIrradiance(20.0, 8.0);
  EXPECT_LT(luminance(hazy), luminance(clear));
  EXPECT_GT(hazy.r / hazy.b, clear.r / clear.b);  // haze reddens the beam
}

}  // namespace
}  // namespace aal
