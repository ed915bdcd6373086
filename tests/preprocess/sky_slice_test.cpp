#include "aperture/preprocess/sky_slice.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(FastAtan, MatchesStdAtanEverywhere) {
  double worst = 0, worstFloat = 0;
  for (double e = -8; e <= 8; e += 1e-4) {
    for (double sign : {-1.0, 1.0}) {
      const double x = sign * std::pow(10.0, e);
      worst = std::max(worst, std::abs(fastAtan(x) - std::atan(x)));
      worstFloat = std::max(worstFloat, double(std::abs(fastAtan(float(x)) - std::atan(float(x)))));
    }
  }
  EXPECT_LT(worst, 2e-6);
  EXPECT_LT(worstFloat, 2e-6);
  EXPECT_EQ(fastAtan(0.0), 0.0);
  EXPECT_NEAR(fastAtan(1e300), kPi / 2, 1e-12);
  EXPECT_EQ(fastAtan(0.0f), 0.0f);
}

// Numerical integral of the slice over elevations above theta0 (midpoint
// rule), the reference for the closed forms.
void integrateSlice(double theta0, double& omega, double& horizontal, double& vertical) {
  constexpr int kSteps = 200000;
  omega = horizontal = vertical = 0;
  const double d = (kPi / 2 - theta0) / kSteps;
  for (int i = 0; i < kSteps; ++i) {
    const double theta = theta0 + (i + 0.5) * d;
    omega += std::cos(theta) * d;
    horizontal += std::cos(theta) * std::cos(theta) * d;
    vertical += std::sin(theta) * std::cos(theta) * d;
  }
}

TEST(SkySlice, ClosedFormsMatchNumericalIntegration) {
  for (double theta0 : {-1.2, -0.5, 0.0, 0.3, 0.9, 1.4}) {
    float sum[4] = {0, 0, 0, 0};
    const double phi = 0.7, dPhi = 0.1;
    skySliceTerms(sum, float(std::tan(theta0)), float(dPhi), float(std::cos(phi) * dPhi),
                  float(std::sin(phi) * dPhi));
    double omega, horizontal, vertical;
    integrateSlice(theta0, omega, horizontal, vertical);
    EXPECT_NEAR(sum[3], dPhi * omega, 1e-6) << theta0;
    EXPECT_NEAR(sum[0], dPhi * std::cos(phi) * horizontal, 1e-6) << theta0;
    EXPECT_NEAR(sum[1], dPhi * std::sin(phi) * horizontal, 1e-6) << theta0;
    EXPECT_NEAR(sum[2], dPhi * vertical, 1e-6) << theta0;
  }
}

// The closed forms in double precision with std::atan, at tangents from
// 1e-8 to 1e8 and up to 1e18: the single-precision terms stay within 1e-6
// (per unit dPhi) of them and finite.
TEST(SkySlice, TermsMatchTheDoublePrecisionClosedFormsAtEveryTangent) {
  const double phi = 2.1, dPhi = 0.3;
  double worst = 0;
  auto check = [&](double t) {
    float term[4];
    skySliceTerms(term, float(t), float(dPhi), float(std::cos(phi) * dPhi),
                  float(std::sin(phi) * dPhi));
    const double tf = float(t), theta = std::atan(tf), s = std::sin(theta);
    const double ic = kPi / 4 - theta / 2 - std::sin(2 * theta) / 4, is = (1 - s * s) / 2;
    const double expected[4] = {std::cos(phi) * dPhi * ic, std::sin(phi) * dPhi * ic, dPhi * is,
                                dPhi * (1 - s)};
    for (int c = 0; c < 4; ++c) {
      ASSERT_TRUE(std::isfinite(term[c])) << t;
      worst = std::max(worst, std::abs(term[c] - expected[c]) / dPhi);
    }
  };
  for (double e = -8; e <= 8; e += 1e-3) {
    check(std::pow(10.0, e));
    check(-std::pow(10.0, e));
  }
  for (double t : {0.0, 1e18, -1e18}) check(t);
  EXPECT_LT(worst, 1e-6);
}

}  // namespace
}  // namespace aal
