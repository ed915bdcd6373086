#include "aperture/terrain/light/caps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

struct CapConfig {
  double r0, r1, d;
};

glm::dvec3 fromPolar(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// Monte Carlo estimate of the intersection area: the fraction of uniformly
// random directions inside both caps, times 4 pi. Returns {estimate, sigma}.
std::pair<double, double> monteCarloIntersection(const CapConfig& c, int samples,
                                                 std::mt19937_64& rng) {
  const glm::dvec3 a(0, 0, 1);
  const glm::dvec3 b = fromPolar(c.d, 0.0);
  const double cos0 = std::cos(c.r0), cos1 = std::cos(c.r1);
  std::normal_distribution<double> normal;
  int inside = 0;
  for (int i = 0; i < samples; ++i) {
    const glm::dvec3 v = glm::normalize(glm::dvec3(normal(rng), normal(rng), normal(rng)));
    if (glm::dot(v, a) >= cos0 && glm::dot(v, b) >= cos1) ++inside;
  }
  const double p = static_cast<double>(inside) / samples;
  return {4 * kPi * p, 4 * kPi * std::sqrt(std::max(p * (1 - p), 1.0 / samples) / samples)};
}

// The Tovchigrechko & Vakser form of docs/design.md §2, written out plainly:
// the reference the production formula (sectors minus triangles) must equal.
double tovchigrechkoVakser(double r0, double r1, double d) {
  if (d >= r0 + r1) return 0.0;
  if (d <= std::abs(r0 - r1)) return capArea(std::min(r0, r1));
  if (r0 + r1 + d >= 2 * kPi) return capArea(r0) + capArea(r1) - 4 * kPi;
  auto acosClamped = [](double x) { return std::acos(std::clamp(x, -1.0, 1.0)); };
  const double c0 = std::cos(r0), c1 = std::cos(r1), cd = std::cos(d);
  const double s0 = std::sin(r0), s1 = std::sin(r1), sd = std::sin(d);
  return 2 * kPi - 2 * acosClamped((cd - c0 * c1) / (s0 * s1)) -
         2 * c0 * acosClamped((c1 - cd * c0) / (sd * s0)) -
         2 * c1 * acosClamped((c0 - cd * c1) / (sd * s1));
}

TEST(CapArea, MatchesKnownSolidAngles) {
  EXPECT_DOUBLE_EQ(capArea(0.0), 0.0);
  EXPECT_NEAR(capArea(kPi / 2), 2 * kPi, 1e-12);
  EXPECT_NEAR(capArea(kPi), 4 * kPi, 1e-12);
  EXPECT_NEAR(capArea(kPi / 3), kPi, 1e-12);  // 2 pi (1 - 1/2)
}

TEST(CapIntersection, ExactMatchesMonteCarloOverAllRadii) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> angle(0.0, kPi);
  constexpr int kSamples = 200000;
  for (int i = 0; i < 60; ++i) {
    const CapConfig c{angle(rng), angle(rng), angle(rng)};
    const auto [estimate, sigma] = monteCarloIntersection(c, kSamples, rng);
    // 5 sigma: a correct formula fails this about once in 3 million configurations.
    EXPECT_NEAR(capIntersectionExact(c.r0, c.r1, c.d), estimate, 5 * sigma)
        << "r0=" << c.r0 << " r1=" << c.r1 << " d=" << c.d;
  }
}

TEST(CapIntersection, ExactMatchesMonteCarloForLargeCaps) {
  std::mt19937_64 rng(777);
  // Caps larger than a hemisphere, including pairs that together cover the sphere.
  const std::vector<CapConfig> configs = {{2.5, 2.0, 1.0}, {2.8, 2.9, 2.0}, {2.0, 1.7, 2.9},
                                          {3.0, 0.5, 2.9}, {1.9, 1.9, 3.1}, {2.2, 1.2, 1.5}};
  for (const CapConfig& c : configs) {
    const auto [estimate, sigma] = monteCarloIntersection(c, 200000, rng);
    EXPECT_NEAR(capIntersectionExact(c.r0, c.r1, c.d), estimate, 5 * sigma)
        << "r0=" << c.r0 << " r1=" << c.r1 << " d=" << c.d;
  }
}

TEST(CapIntersection, EqualsTheTovchigrechkoVakserForm) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> angle(0.0, kPi);
  for (int i = 0; i < 100000; ++i) {
    const double r0 = angle(rng), r1 = angle(rng), d = angle(rng);
    // The reference itself is only good to ~1e-7 near its branch boundaries.
    EXPECT_NEAR(capIntersectionExact(r0, r1, d), tovchigrechkoVakser(r0, r1, d), 1e-6)
        << "r0=" << r0 << " r1=" << r1 << " d=" << d;
  }
}

TEST(CapIntersection, SmallCapsMatchThePlanarLens) {
  // A cap of 0.27 degrees (the sun) against a larger one: for small caps the
  // sphere is locally flat, so the area tends to the planar lens area
  // (relative difference O(r^2) ~ 1e-5 here).
  const double rs = 0.00465, ra = 0.006;
  for (double d = 0.0016; d < rs + ra; d += 0.0005) {
    const double a0 = std::acos((d * d + rs * rs - ra * ra) / (2 * d * rs));
    const double a1 = std::acos((d * d + ra * ra - rs * rs) / (2 * d * ra));
    const double lens =
        rs * rs * (a0 - std::sin(2 * a0) / 2) + ra * ra * (a1 - std::sin(2 * a1) / 2);
    EXPECT_NEAR(capIntersectionExact(rs, ra, d), lens, 1e-4 * capArea(rs)) << "d=" << d;
  }
}

TEST(CapIntersection, TwoHemispheresMeetInALune) {
  // Hemispheres whose poles are d apart intersect in a lune of angle pi - d.
  for (double d = 0.0; d <= kPi; d += kPi / 16) {
    EXPECT_NEAR(capIntersectionExact(kPi / 2, kPi / 2, d), 2 * (kPi - d), 1e-9) << "d=" << d;
  }
}

TEST(CapIntersection, DegenerateConfigurations) {
  EXPECT_NEAR(capIntersectionExact(0.7, 1.2, 0.0), capArea(0.7), 1e-12);  // d = 0: nested
  EXPECT_DOUBLE_EQ(capIntersectionExact(0.7, 1.2, kPi), 0.0);             // opposite, disjoint
  // Opposite caps that overlap: the band where both reach.
  EXPECT_NEAR(capIntersectionExact(2.0, 2.0, kPi), capArea(2.0) * 2 - 4 * kPi, 1e-12);
  EXPECT_DOUBLE_EQ(capIntersectionExact(0.0, 1.0, 0.5), 0.0);  // r = 0
  EXPECT_DOUBLE_EQ(capIntersectionExact(0.0, 0.0, 0.0), 0.0);
  EXPECT_NEAR(capIntersectionExact(kPi, 0.8, 2.0), capArea(0.8), 1e-12);  // whole sphere
  EXPECT_NEAR(capIntersectionExact(kPi, kPi, kPi), 4 * kPi, 1e-12);       // both cover it
  EXPECT_NEAR(capIntersectionExact(kPi, kPi, 0.0), 4 * kPi, 1e-12);
}

TEST(CapIntersection, SymmetricInTheTwoRadii) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> angle(0.0, kPi);
  for (int i = 0; i < 10000; ++i) {
    const double r0 = angle(rng), r1 = angle(rng), d = angle(rng);
    EXPECT_NEAR(capIntersectionExact(r0, r1, d), capIntersectionExact(r1, r0, d), 1e-12);
    EXPECT_EQ(capIntersectionApprox(float(r0), float(r1), float(d)),
              capIntersectionApprox(float(r1), float(r0), float(d)));
  }
}

TEST(CapIntersection, ContinuousAcrossEveryBranchBoundary) {
  // Approach each boundary from both sides; the area may change by at most
  // what its slope allows over the step (|dA/dd| <= 2 pi, the longest
  // boundary circle), so a jump between branches would show.
  constexpr double kEps = 1e-7;
  constexpr double kTol = 4 * kPi * kEps + 1e-9;
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> angle(0.05, kPi - 0.05);
  for (int i = 0; i < 2000; ++i) {
    const double r0 = angle(rng), r1 = angle(rng);
    const std::vector<double> boundaries = {r0 + r1, std::abs(r0 - r1), 2 * kPi - r0 - r1};
    for (double b : boundaries) {
      if (b <= kEps || b >= kPi - kEps) continue;
      const double below = capIntersectionExact(r0, r1, b - kEps);
      const double above = capIntersectionExact(r0, r1, b + kEps);
      EXPECT_NEAR(below, above, kTol) << "r0=" << r0 << " r1=" << r1 << " boundary d=" << b;
    }
  }
}

TEST(CapIntersection, ContinuousInTheRadiiAtZeroAndPi) {
  for (double d : {0.3, 1.5, 2.9}) {
    EXPECT_NEAR(capIntersectionExact(1e-9, 1.0, d), capIntersectionExact(0.0, 1.0, d), 1e-9);
    EXPECT_NEAR(capIntersectionExact(kPi - 1e-9, 1.0, d), capIntersectionExact(kPi, 1.0, d), 1e-6);
  }
}

TEST(CapIntersection, DecreasesMonotonicallyWithDistance) {
  constexpr double kRounding = 1e-12;
  for (int i = 1; i <= 24; ++i) {
    for (int j = 1; j <= 24; ++j) {
      const double r0 = kPi * i / 24, r1 = kPi * j / 24;
      double previous = capIntersectionExact(r0, r1, 0.0);
      for (int k = 1; k <= 720; ++k) {
        const double area = capIntersectionExact(r0, r1, kPi * k / 720);
        ASSERT_LE(area, previous + kRounding) << "r0=" << r0 << " r1=" << r1 << " k=" << k;
        previous = area;
      }
    }
  }
}

TEST(CapIntersection, NeverExceedsTheSmallerCap) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> angle(0.0, kPi);
  for (int i = 0; i < 100000; ++i) {
    const double r0 = angle(rng), r1 = angle(rng), d = angle(rng);
    const double area = capIntersectionExact(r0, r1, d);
    EXPECT_GE(area, 0.0);
    EXPECT_LE(area, capArea(std::min(r0, r1)) + 1e-12);
  }
}

// The listing of Oat, "Ambient Aperture Lighting", 2006, transcribed
// literally, HLSL intrinsics included.
float hlslSaturate(float x) {
  return std::min(std::max(x, 0.0f), 1.0f);
}
float hlslSmoothstep(float a, float b, float x) {
  const float t = hlslSaturate((x - a) / (b - a));
  return t * t * (3.0f - 2.0f * t);
}
float oatListing(float fRadius0, float fRadius1, float fDist) {
  float fArea;
  if (fDist <= std::max(fRadius0, fRadius1) - std::min(fRadius0, fRadius1)) {
    fArea = 6.283185308f - 6.283185308f * std::cos(std::min(fRadius0, fRadius1));
  } else if (fDist >= fRadius0 + fRadius1) {
    fArea = 0;
  } else {
    float fDiff = std::abs(fRadius0 - fRadius1);
    fArea = hlslSmoothstep(0.0f, 1.0f,
                           1.0f - hlslSaturate((fDist - fDiff) / (fRadius0 + fRadius1 - fDiff)));
    fArea *= 6.283185308f - 6.283185308f * std::cos(std::min(fRadius0, fRadius1));
  }
  return fArea;
}

TEST(CapIntersectionApprox, EqualsOatsListing) {
  for (int i = 0; i <= 40; ++i) {
    for (int j = 0; j <= 40; ++j) {
      for (int k = 0; k <= 80; ++k) {
        const float r0 = float(kPi * i / 40), r1 = float(kPi * j / 40), d = float(kPi * k / 80);
        ASSERT_FLOAT_EQ(capIntersectionApprox(r0, r1, d), oatListing(r0, r1, d))
            << r0 << " " << r1 << " " << d;
      }
    }
  }
}

TEST(CapIntersectionApprox, ExactInTheTrivialCases) {
  EXPECT_FLOAT_EQ(capIntersectionApprox(0.3f, 0.4f, 0.8f), 0.0f);            // disjoint
  EXPECT_NEAR(capIntersectionApprox(0.3f, 1.0f, 0.5f), capArea(0.3), 1e-5);  // nested
}

TEST(VisibleLightCentroid, IsTheLightItselfWhenAllOfItIsVisible) {
  const glm::vec3 b(0, 0, 1), l(std::sqrt(0.5f), 0, std::sqrt(0.5f));
  EXPECT_EQ(visibleLightCentroid(b, l, 0.785f, 0.00465f, 1.0f), l);
}

TEST(VisibleLightCentroid, LeansTowardsTheBentNormalAsTheApertureCutsTheLight) {
  const glm::vec3 b(0, 0, 1), l(1, 0, 0);  // 90 degrees apart
  const float r = 0.1f;
  float previous = 0;
  for (float f : {0.75f, 0.5f, 0.25f, 0.0f}) {
    const glm::vec3 c = visibleLightCentroid(b, l, 1.5708f, r, f);
    EXPECT_NEAR(glm::length(c), 1.0f, 1e-6f);
    EXPECT_NEAR(c.y, 0.0f, 1e-7f);  // on the great circle through B and L
    const float shift = std::atan2(c.z, c.x);
    EXPECT_NEAR(shift, (1 - f) * r, 1e-6f) << f;
    EXPECT_GT(shift, previous);
    previous = shift;
  }
}

TEST(VisibleLightCentroid, NeverPassesTheBentNormal) {
  // A light larger than its distance to B: the shift stops at B.
  const glm::vec3 b(0, 0, 1), l(std::sin(0.05f), 0, std::cos(0.05f));
  const glm::vec3 c = visibleLightCentroid(b, l, 0.05f, 0.5f, 0.0f);
  EXPECT_NEAR(glm::dot(c, b), 1.0f, 1e-6f);
  EXPECT_EQ(visibleLightCentroid(b, b, 0.0f, 0.5f, 0.3f), b);  // nothing to lean towards
}

}  // namespace
}  // namespace aal
