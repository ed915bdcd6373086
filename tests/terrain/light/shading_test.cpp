#include "aperture/terrain/light/shading.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/caps.h"

namespace aal {
namespace {

constexpr float kPi = std::numbers::pi_v<float>;

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
  // normalize(B + L) of Oat 2006, which would give cos 22.5 here).
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

// Closed forms of the sky and sun terms, by quadrature over the
// sphere here rather than by the shading code's helpers: the same error in
// terrain/light/shading.cpp and shaders/shading.glsl passes their parity test, and
// at r = pi/2 with N = B the sky term cannot tell sin^2 r from sin r.

// A unit vector at polar angle theta and azimuth phi about `axis`.
glm::dvec3 around(const glm::dvec3& axis, double theta, double phi) {
  const glm::dvec3 helper = std::abs(axis.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0);
  const glm::dvec3 u = glm::normalize(glm::cross(helper, axis)), v = glm::cross(axis, u);
  return std::cos(theta) * axis + std::sin(theta) * (std::cos(phi) * u + std::sin(phi) * v);
}

// The integral of g(omega) d omega over the cap of arc length r about `axis`,
// midpoint rule in (theta, phi) with d omega = sin theta d theta d phi.
template <class G>
double capIntegral(const glm::dvec3& axis, double r, const G& g, int steps = 600) {
  double sum = 0;
  const double dTheta = r / steps, dPhi = 2 * std::acos(-1.0) / (2 * steps);
  for (int i = 0; i < steps; ++i) {
    const double theta = (i + 0.5) * dTheta;
    for (int j = 0; j < 2 * steps; ++j) {
      sum += g(around(axis, theta, (j + 0.5) * dPhi)) * std::sin(theta) * dTheta * dPhi;
    }
  }
  return sum;
}

struct TiltedAperture {
  glm::dvec3 normal, bent;
  double radius, tiltRad;
};

// N = up, B tilted from it by `tiltDeg` towards azimuth 30 degrees: the
// apertures of the tests, r below and at pi/2.
std::vector<TiltedAperture> tiltedApertures() {
  std::vector<TiltedAperture> out;
  for (const double r : {0.3, 0.8, 1.2, double(kPi) / 2}) {
    for (const double tiltDeg : {0.0, 20.0, 50.0}) {
      const double beta = tiltDeg * kPi / 180, az = 30 * kPi / 180;
      out.push_back({{0, 0, 1},
                     {std::sin(beta) * std::cos(az), std::sin(beta) * std::sin(az), std::cos(beta)},
                     r,
                     beta});
    }
  }
  return out;
}

ShadingInputs inputsFor(const TiltedAperture& a, const glm::dvec3& sun) {
  ShadingInputs in = openGround();
  in.albedo = glm::vec3(0.3f, 0.5f, 0.7f);
  in.normal = glm::vec3(a.normal);
  in.bentNormal = glm::vec3(a.bent);
  in.apertureRad = float(a.radius);
  in.sunDirection = glm::vec3(sun);
  in.transfer = glm::vec3(0.9f, 0.8f, 0.6f);
  return in;
}

TEST(Shading, SkyTermIsTheIrradianceOfAUniformCapAboutTheBentNormal) {
  // E_sky = L_sky times the cosine-weighted solid angle of the aperture
  // (Oat, "Ambient Aperture Lighting", 2006; Lambertian surface, uniform
  // sky). Where the cap lies above
  // N's horizon (tilt + r <= pi/2) that is the irradiance itself, the
  // integral of max(0, N.w). Where it dips below, the model takes the cap's
  // vector irradiance pi sin^2(r) B projected on N: the integral of N.w,
  // the part below the horizon counting negatively.
  for (const TiltedAperture& a : tiltedApertures()) {
    const bool aboveHorizon = a.tiltRad + a.radius <= kPi / 2 + 1e-9;
    const double cosineArea = capIntegral(a.bent, a.radius, [&](const glm::dvec3& w) {
      const double c = glm::dot(a.normal, w);
      return aboveHorizon ? std::max(0.0, c) : c;
    });
    // The sun well outside the aperture: none of the sky is its share.
    const glm::dvec3 sun = around(a.bent, a.radius + 0.1, 1.0);
    const ShadingInputs in = inputsFor(a, sun);
    for (ShadingMode mode : {ShadingMode::Approx, ShadingMode::Exact}) {
      const ShadingTerms t = shadingTerms(in, mode);
      ASSERT_EQ(t.sunFraction, 0.0f);
      const double expected = 5.0 * cosineArea;
      EXPECT_NEAR(t.skyIrradiance.g, expected, 1e-4 * kPi * 5.0)
          << "r " << a.radius << " tilt " << a.tiltRad << " mode " << int(mode);
      EXPECT_NEAR(t.ambient.b, 0.7 / kPi * expected * 0.6, 1e-4 * 0.7 * 5.0)
          << "r " << a.radius << " tilt " << a.tiltRad;
    }
    EXPECT_NEAR(shade(in, ShadingMode::DebugSkyFill).r, cosineArea / kPi, 1e-4)
        << "r " << a.radius << " tilt " << a.tiltRad;
  }
}

TEST(Shading, SunTermIsTheLambertIrradianceOfTheVisiblePartOfTheDisk) {
  // direct = a/pi E_sun (1/A_s) integral over the sun's disk of
  // [w inside the aperture] max(0, N.w): the sun well inside the aperture,
  // across its rim (half hidden) and just outside, leaning partly towards N.
  const double sunRadius = 0.004653;
  int halfHiddenAndLit = 0;  // the cases that tell the centroid's Lambert term apart
  for (const TiltedAperture& a : tiltedApertures()) {
    for (const double offset : {-0.5 * a.radius, 0.0, 3 * sunRadius}) {
      const double d = a.radius + offset;
      const glm::dvec3 sun = around(a.bent, d, 2.0);
      const auto visible = [&](const glm::dvec3& w) {
        return std::atan2(glm::length(glm::cross(w, a.bent)), glm::dot(w, a.bent)) <= a.radius;
      };
      // The disk's own quadrature as the area: its discretisation cancels.
      const double area = capIntegral(
          sun, sunRadius, [](const glm::dvec3&) { return 1.0; }, 200);
      const double fraction =
          capIntegral(
              sun, sunRadius, [&](const glm::dvec3& w) { return visible(w) ? 1.0 : 0.0; }, 200) /
          area;
      const double lambert = capIntegral(
                                 sun, sunRadius,
                                 [&](const glm::dvec3& w) {
                                   return visible(w) ? std::max(0.0, glm::dot(a.normal, w)) : 0.0;
                                 },
                                 200) /
                             area;
      ShadingInputs in = inputsFor(a, sun);
      in.sunRadiusRad = float(sunRadius);
      const ShadingTerms t = shadingTerms(in, ShadingMode::Exact);
      EXPECT_NEAR(t.sunFraction, fraction, 2e-3)
          << "r " << a.radius << " tilt " << a.tiltRad << " sun " << d;
      EXPECT_NEAR(t.direct.r, 0.3 / kPi * 100.0 * lambert, 1e-3 * 0.3 / kPi * 100.0)
          << "r " << a.radius << " tilt " << a.tiltRad << " sun " << d;
      halfHiddenAndLit += fraction > 0.3 && fraction < 0.7 && lambert > 0.1;
    }
  }
  EXPECT_GE(halfHiddenAndLit, 8);
}

TEST(Shading, DebugViewsShowTheirQuantities) {
  ShadingInputs in = openGround();
  in.apertureRad = 1.0f;
  EXPECT_NEAR(shade(in, ShadingMode::DebugVisible).r, 1 - std::cos(1.0f), 1e-6f);
  in.bentNormal = glm::vec3(1, 0, 0);
  EXPECT_NEAR(shade(in, ShadingMode::DebugBentNormal).r, 1.0f, 1e-6f);
  EXPECT_NEAR(shade(in, ShadingMode::DebugBentNormal).g, 0.5f, 1e-6f);
}

TEST(Shading, TheSunsEdgeOverAFootprintIsTheMeanOfItsStep) {
  // Brute force: the mean of the visible fraction over a footprint whose
  // d spreads uniformly over a box of standard deviation sigma (width
  // sigma sqrt(12)), 2001 points, against the fraction at
  // sunEdgeFootprintDistance's distance; d sweeps the edge. Python's
  // model of the same read max errors of 0.04 (exact) and 0.02 (approx) up to
  // sigma = 0.02 against 0.13-0.43 for the fraction at the mean d.
  const float sun = ShadingInputs{}.sunRadiusRad;
  const double area = capArea(sun);
  for (const bool exact : {false, true}) {
    const auto fraction = [&](float r, float d) {
      return (exact ? capIntersectionExact(r, sun, d) : capIntersectionApprox(r, sun, d)) / area;
    };
    for (const float r : {0.5f, 1.2f}) {
      for (const float sigma : {0.003f, 0.01f, 0.02f}) {
        const float width = sigma * std::sqrt(12.0f);
        double worst = 0, worstPoint = 0, squares = 0, squaresPoint = 0;
        const int steps = 201;
        for (int i = 0; i < steps; ++i) {
          const float d = r + 4.0f * (sun + width) * (2.0f * float(i) / (steps - 1) - 1.0f);
          double mean = 0;
          for (int k = 0; k < 2001; ++k) mean += fraction(r, d + width * (float(k) / 2000 - 0.5f));
          mean /= 2001;
          const double filtered = fraction(r, sunEdgeFootprintDistance(r, sun, d, sigma));
          const double point = fraction(r, d);
          worst = std::max(worst, std::abs(filtered - mean));
          worstPoint = std::max(worstPoint, std::abs(point - mean));
          squares += (filtered - mean) * (filtered - mean);
          squaresPoint += (point - mean) * (point - mean);
        }
        std::printf("%s r %.1f sigma %.3f: max error %.3f (at the mean d %.3f), rms %.4f (%.4f)\n",
                    exact ? "exact " : "approx", r, sigma, worst, worstPoint,
                    std::sqrt(squares / steps), std::sqrt(squaresPoint / steps));
        EXPECT_LT(worst, 0.06) << exact << " " << r << " " << sigma;
        EXPECT_LT(squares, 0.25 * squaresPoint) << exact << " " << r << " " << sigma;
      }
    }
  }
  // No spread, or an aperture no larger than the sun: the distance as given.
  EXPECT_EQ(sunEdgeFootprintDistance(0.8f, sun, 0.8123f, 0.0f), 0.8123f);
  EXPECT_EQ(sunEdgeFootprintDistance(sun, sun, 0.01f, 0.01f), 0.01f);
  // Across a depth edge the spread is the two surfaces', not a footprint's:
  // the widening stops at AAL_SUN_EDGE_MAX_WIDENING_RAD.
  const float farOut = sunEdgeFootprintDistance(0.8f, sun, 0.8f + 0.1f, 10.0f);
  EXPECT_NEAR(farOut - 0.8f, 0.1f * sun / (sun + float(AAL_SUN_EDGE_MAX_WIDENING_RAD)), 1e-6f);
}

}  // namespace
}  // namespace aal
