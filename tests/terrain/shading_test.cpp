#include "shading.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

#include "caps.h"

namespace aal {
namespace {

constexpr float kPi = 3.14159265358979323846f;

ShadingInputs openGround() {
  ShadingInputs in;
  in.albedo = glm::vec3(0.3f);
  in.sunIrradiance = glm::vec3(100.0f);
  in.skyRadiance = glm::vec3(5.0f);
  in.sunDirection = glm::normalize(glm::vec3(1, 0, 1));
  return in;
}

TEST(Shading, OpenFlatGroundIsLambertPlusTheWholeSky) {
  const ShadingInputs in = openGround();
  const ShadingTerms t = shadingTerms(in, ShadingMode::Exact);
  EXPECT_FLOAT_EQ(t.sunFraction, 1.0f);
  // The whole sun is visible: the Lambert term is N.L itself (not the
  // normalize(B + L) of seed 002, which would give cos 22.5 here).
  EXPECT_NEAR(t.direct.r, 0.3f / kPi * 100.0f * std::cos(kPi / 4), 1e-4f);
  EXPECT_NEAR(t.direct.r, shadingTerms(in, ShadingMode::BaselineLambert).direct.r, 1e-5f);
  // The open hemisphere: pi sin^2(pi/2) L_sky, minus the sun's tiny share.
  EXPECT_NEAR(t.skyIrradiance.r, kPi * 5.0f, 1e-3f);
}

TEST(Shading, SunOutsideTheApertureGivesShadow) {
  ShadingInputs in = openGround();
  in.apertureRad = 0.3f;  // a narrow pit: the sun at 45 degrees is outside
  for (ShadingMode mode : {ShadingMode::Approx, ShadingMode::Exact}) {
    const ShadingTerms t = shadingTerms(in, mode);
    EXPECT_EQ(t.sunFraction, 0.0f);
    EXPECT_EQ(t.direct.r, 0.0f);
    EXPECT_GT(t.ambient.r, 0.0f);
  }
}

TEST(Shading, SunOnTheRimIsHalfVisible) {
  ShadingInputs in = openGround();
  in.apertureRad = kPi / 4;  // the sun's centre exactly on the aperture's rim
  const ShadingTerms t = shadingTerms(in, ShadingMode::Exact);
  EXPECT_NEAR(t.sunFraction, 0.5f, 0.01f);
}

TEST(Shading, ApproxAndExactDifferByAtMostTheCapError) {
  // Only the sun fraction differs; its error is the cap intersection error
  // relative to the smaller cap (the sun): at most 15.9% for apertures <= 90
  // degrees (docs/caps.md).
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  double worst = 0;
  for (int i = 0; i < 20000; ++i) {
    ShadingInputs in = openGround();
    in.apertureRad = 0.1f + 1.47f * unit(rng);
    in.sunRadiusRad = 0.00465f * (1 + 20 * unit(rng));
    const float angle = in.apertureRad + (unit(rng) - 0.5f) * 4 * in.sunRadiusRad;
    in.sunDirection = glm::vec3(std::sin(angle), 0, std::cos(angle));
    const ShadingTerms a = shadingTerms(in, ShadingMode::Approx);
    const ShadingTerms e = shadingTerms(in, ShadingMode::Exact);
    const double df = std::abs(a.sunFraction - e.sunFraction);
    worst = std::max(worst, df);
    ASSERT_LE(df, 0.16) << "aperture " << in.apertureRad << " sun " << in.sunRadiusRad;
  }
  EXPECT_GT(worst, 0.05);  // the approximation is visibly different near the rim
}

TEST(Shading, BaselinesIgnoreTheAperture) {
  ShadingInputs in = openGround();
  in.apertureRad = 0.2f;
  const glm::vec3 lambert = shade(in, ShadingMode::BaselineLambert);
  EXPECT_NEAR(lambert.r, 0.3f / kPi * (100.0f * std::cos(kPi / 4) + kPi * 5.0f), 1e-3f);
  const glm::vec3 ao = shade(in, ShadingMode::BaselineAo);
  EXPECT_NEAR(ao.r, 0.3f / kPi * (100.0f * std::cos(kPi / 4) + kPi * 5.0f * (1 - std::cos(0.2f))),
              1e-3f);
}

TEST(Shading, DebugViewsShowTheirQuantities) {
  ShadingInputs in = openGround();
  in.apertureRad = 1.0f;
  EXPECT_NEAR(shade(in, ShadingMode::DebugVisible).r, 1 - std::cos(1.0f), 1e-6f);
  in.bentNormal = glm::vec3(1, 0, 0);
  EXPECT_NEAR(shade(in, ShadingMode::DebugBentNormal).r, 1.0f, 1e-6f);
  EXPECT_NEAR(shade(in, ShadingMode::DebugBentNormal).g, 0.5f, 1e-6f);
}

}  // namespace
}  // namespace aal
