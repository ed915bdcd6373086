#include "aperture/terrain/light/cap_table.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

// u at pi/2: the largest u of a tabulated aperture.
double largestU(double lightRadiusRad) {
  return (0.5 * kPi - lightRadiusRad) / (0.5 * kPi + lightRadiusRad);
}

// The fraction of a small disk (the aperture as r_a -> 0) on the sun's side
// of the sun's rim, which at that scale is straight: the disk's centre lies
// (2t - 1) radii outside it.
double vanishingApertureFraction(double t) {
  const double u = std::clamp(2.0 * t - 1.0, -1.0, 1.0);
  return (std::acos(u) - u * std::sqrt(1.0 - u * u)) / kPi;
}

}  // namespace

float capTableRow(float apertureRad, float lightRadiusRad) {
  const float u = (apertureRad - lightRadiusRad) / (apertureRad + lightRadiusRad);
  const float uMax = (0.5f * float(kPi) - lightRadiusRad) / (0.5f * float(kPi) + lightRadiusRad);
  const float w = u > 0.0f ? std::sqrt(u / uMax) : -std::sqrt(-u);
  return 0.5f + 0.5f * w;
}

double capTableAperture(double s, double lightRadiusRad) {
  const double w = 2.0 * s - 1.0;
  const double u = w > 0.0 ? w * w * largestU(lightRadiusRad) : -w * w;
  return lightRadiusRad * (1.0 + u) / (1.0 - u);
}

CapIntersectionTable makeCapIntersectionTable(float lightRadiusRad) {
  if (!(lightRadiusRad > 0.0f && lightRadiusRad < 0.5f * float(kPi))) {
    throw std::invalid_argument(
        "makeCapIntersectionTable: the light's radius must be in (0, pi/2)");
  }
  CapIntersectionTable table;
  table.lightRadiusRad = lightRadiusRad;
  table.values.resize(size_t{AAL_CAP_TABLE_WIDTH} * AAL_CAP_TABLE_HEIGHT);
  const double rs = lightRadiusRad;
  for (int row = 0; row < AAL_CAP_TABLE_HEIGHT; ++row) {
    const double s = double(row) / (AAL_CAP_TABLE_HEIGHT - 1);
    const double ra = row == AAL_CAP_TABLE_HEIGHT - 1 ? 0.5 * kPi : capTableAperture(s, rs);
    const double smaller = std::min(ra, rs);
    for (int column = 0; column < AAL_CAP_TABLE_WIDTH; ++column) {
      const double t = double(column) / (AAL_CAP_TABLE_WIDTH - 1);
      double g;
      if (row == 0) {
        g = vanishingApertureFraction(t);  // the limit r_a -> 0 (both areas vanish)
      } else {
        const double d = std::abs(ra - rs) + 2.0 * smaller * t;
        g = capIntersectionExact(ra, rs, d) / capArea(smaller);
      }
      table.values[size_t(row) * AAL_CAP_TABLE_WIDTH + size_t(column)] =
          static_cast<float>(std::clamp(g, 0.0, 1.0));
    }
  }
  return table;
}

float capIntersectionFromTable(const CapIntersectionTable& table, float apertureRad, float dRad) {
  const float pi = float(kPi);
  const float rs = table.lightRadiusRad;
  float ra = std::clamp(apertureRad, 0.0f, pi);
  float d = std::clamp(dRad, 0.0f, pi);
  // Beyond a hemisphere: the sun less its part in the complement cap.
  const bool flip = ra > 0.5f * pi;
  if (flip) {
    ra = pi - ra;
    d = pi - d;
  }
  const float smaller = std::min(ra, rs);
  const float t = (d - std::abs(ra - rs)) / (2.0f * std::max(smaller, 1e-30f));
  // Bilinear between texel centres (column t (W - 1), row s (H - 1)), as a
  // sampler with linear filtering and clamp to edge reads the texture.
  const float x = std::clamp(t, 0.0f, 1.0f) * float(AAL_CAP_TABLE_WIDTH - 1);
  const float y = std::clamp(capTableRow(ra, rs), 0.0f, 1.0f) * float(AAL_CAP_TABLE_HEIGHT - 1);
  const int x0 = std::min(int(x), AAL_CAP_TABLE_WIDTH - 2);
  const int y0 = std::min(int(y), AAL_CAP_TABLE_HEIGHT - 2);
  const float fx = x - float(x0), fy = y - float(y0);
  const auto at = [&](int column, int row) {
    return table.values[size_t(row) * AAL_CAP_TABLE_WIDTH + size_t(column)];
  };
  const float g = (1.0f - fy) * ((1.0f - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) +
                  fy * ((1.0f - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
  const float area = static_cast<float>(capArea(smaller));
  float inside = t <= 0.0f ? area : t >= 1.0f ? 0.0f : area * g;
  if (!(smaller > 0.0f)) inside = 0.0f;
  return flip ? static_cast<float>(capArea(rs)) - inside : inside;
}

}  // namespace aal
