// The exact cap intersection read from a table (terrain/light/cap_table.h) follows
// the closed form (terrain/light/caps.h) to 1e-3 of the smaller cap's area.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>
#include <stdexcept>

#include <glm/geometric.hpp>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/cap_table.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/light/shading.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

// The thinnest sun the tools allow (0.01 degrees), the real one, and larger
// ones up to the tools' 20 degrees.
constexpr float kSunRadii[] = {0.000174533f, 0.004653f, 0.02f, 0.1f, 0.349066f};

// Worst |table - closed form| / A(min(r_a, r_s)) over a dense grid: apertures
// of every size (finely around the sun's size, where the two caps nearly
// coincide), distances across the band where the area changes and a little
// beyond it, and over all of [0, pi].
double worstRelativeError(const CapIntersectionTable& table, double* worstRa, double* worstD) {
  const float rs = table.lightRadiusRad;
  double worst = 0;
  const auto check = [&](float ra, float d) {
    const double smaller = capArea(std::min<double>(ra, rs));
    const double error =
        std::abs(double(capIntersectionFromTable(table, ra, d)) - capIntersectionExact(ra, rs, d));
    // Float rounding of A(r_s) - inside beyond a hemisphere: a few ulps of the sun.
    const double relative = (error - 1e-6 * capArea(rs)) / smaller;
    if (smaller > 0 && relative > worst) {
      worst = relative;
      *worstRa = ra;
      *worstD = d;
    }
  };
  for (int a = 0; a <= 1500; ++a) {
    const float ra =
        a <= 500 ? 3.0f * rs * float(a) / 500.0f : float(kPi) * float(a - 500) / 1000.0f;
    const float lo = std::max(0.0f, std::abs(ra - rs) - 0.05f * rs);
    const float hi = std::min(float(kPi), ra + rs + 0.05f * rs);
    for (int k = 0; k <= 300; ++k) check(ra, lo + (hi - lo) * float(k) / 300.0f);
    for (int k = 0; k <= 50; ++k) check(ra, float(kPi) * float(k) / 50.0f);
  }
  return worst;
}

TEST(CapTable, FollowsTheClosedFormWithinAThousandthOfTheSmallerCap) {
  for (const float rs : kSunRadii) {
    const CapIntersectionTable table = makeCapIntersectionTable(rs);
    double ra = 0, d = 0;
    const double worst = worstRelativeError(table, &ra, &d);
    std::printf("sun %.6f rad: worst error %.3g of the smaller cap (r_a %.6g, d %.6g)\n", rs, worst,
                ra, d);
    EXPECT_LE(worst, 1e-3) << "sun " << rs << " at r_a " << ra << " d " << d;
  }
}

// A table whose rows are blended with the row above (values for somewhat
// smaller apertures) misses the bound: the check above can fail.
TEST(CapTable, AWorseTableFailsTheSameCheck) {
  CapIntersectionTable table = makeCapIntersectionTable(0.004653f);
  // Shift every row by half a row: values for the wrong apertures.
  for (int row = AAL_CAP_TABLE_HEIGHT - 1; row > 0; --row) {
    for (int column = 0; column < AAL_CAP_TABLE_WIDTH; ++column) {
      float& v = table.values[size_t(row) * AAL_CAP_TABLE_WIDTH + size_t(column)];
      v = 0.5f * (v + table.values[size_t(row - 1) * AAL_CAP_TABLE_WIDTH + size_t(column)]);
    }
  }
  double ra = 0, d = 0;
  EXPECT_GT(worstRelativeError(table, &ra, &d), 1e-3);
}

TEST(CapTable, RowsRunFromFullToEmptyAndTheSunSizedApertureIsARow) {
  for (const float rs : kSunRadii) {
    const CapIntersectionTable table = makeCapIntersectionTable(rs);
    ASSERT_EQ(table.values.size(), size_t{AAL_CAP_TABLE_WIDTH} * AAL_CAP_TABLE_HEIGHT);
    for (int row = 0; row < AAL_CAP_TABLE_HEIGHT; ++row) {
      const float* g = &table.values[size_t(row) * AAL_CAP_TABLE_WIDTH];
      EXPECT_NEAR(g[0], 1.0f, 1e-6f) << "row " << row;
      EXPECT_NEAR(g[AAL_CAP_TABLE_WIDTH - 1], 0.0f, 1e-6f) << "row " << row;
      for (int c = 1; c < AAL_CAP_TABLE_WIDTH; ++c) EXPECT_LE(g[c], g[c - 1] + 1e-7f);
    }
    // The row map and its inverse; r_s on the middle row, pi/2 on the last.
    EXPECT_NEAR(capTableAperture(0.5, rs), rs, 1e-9 * rs);
    EXPECT_NEAR(capTableAperture(1.0, rs), 0.5 * kPi, 1e-9);
    EXPECT_EQ(capTableAperture(0.0, rs), 0.0);
    for (double s = 0.0; s <= 1.0; s += 0.01) {
      EXPECT_NEAR(capTableRow(float(capTableAperture(s, rs)), rs), s, 2e-6) << s;
    }
  }
  EXPECT_THROW(makeCapIntersectionTable(0.0f), std::invalid_argument);
  EXPECT_THROW(makeCapIntersectionTable(1.6f), std::invalid_argument);
}

TEST(CapTable, EdgeCasesAreTheClosedFormsOwn) {
  const CapIntersectionTable table = makeCapIntersectionTable(0.004653f);
  const double sun = capArea(0.004653);
  EXPECT_EQ(capIntersectionFromTable(table, 0.0f, 0.0f), 0.0f);                     // no aperture
  EXPECT_NEAR(capIntersectionFromTable(table, float(kPi), 1.0f), sun, 1e-6 * sun);  // all sky
  EXPECT_NEAR(capIntersectionFromTable(table, 1.0f, 0.5f), sun, 1e-6 * sun);        // inside
  EXPECT_EQ(capIntersectionFromTable(table, 1.0f, 1.5f), 0.0f);                     // outside
  // Half a sun at the rim of an open sky (a great circle cuts it in two).
  EXPECT_NEAR(capIntersectionFromTable(table, float(0.5 * kPi), float(0.5 * kPi)), 0.5 * sun,
              1e-3 * sun);
}

// Exact shading through the table (the renderer's) against exact shading
// through the closed form: the sun's visible fraction within 1e-3.
TEST(CapTable, ExactShadingThroughTheTableFollowsTheClosedForm) {
  std::mt19937 rng(18);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const float rs : kSunRadii) {
    const CapIntersectionTable table = makeCapIntersectionTable(rs);
    for (int i = 0; i < 2000; ++i) {
      ShadingInputs in;
      in.sunRadiusRad = rs;
      in.sunIrradiance = glm::vec3(100.0f);
      in.skyRadiance = glm::vec3(5.0f);
      in.apertureRad = 0.02f + 1.6f * unit(rng);
      const float beta = 0.6f * unit(rng);
      in.bentNormal = {std::sin(beta), 0.0f, std::cos(beta)};
      // The sun within a sun's diameter of the aperture's rim.
      const float d = in.apertureRad + rs * (4.0f * unit(rng) - 2.0f);
      in.sunDirection = glm::normalize(std::cos(d) * in.bentNormal +
                                       std::sin(d) * glm::vec3(-std::cos(beta), 0, std::sin(beta)));
      const ShadingTerms closed = shadingTerms(in, ShadingMode::Exact);
      const ShadingTerms tabled = shadingTerms(in, ShadingMode::Exact, &table);
      EXPECT_NEAR(tabled.sunFraction, closed.sunFraction, 1e-3f) << "sun " << rs << " i " << i;
    }
  }
}

}  // namespace
}  // namespace aal
