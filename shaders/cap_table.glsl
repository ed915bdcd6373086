// The exact cap intersection against the sun read from a table: twin of
// capIntersectionFromTable in terrain/light/cap_table.h (see there and
// docs/caps.md for the parametrisation). The table is made for one sun
// radius (the renderer's, when it changes); lightRadiusRad must be that one.
#ifndef AAL_CAP_TABLE_GLSL
#define AAL_CAP_TABLE_GLSL

#include "caps.glsl"
#include "config.h"

// Row coordinate in [0, 1] of an aperture in [0, pi/2] (capTableRow).
float capTableRow(float apertureRad, float lightRadiusRad) {
  const float halfPi = 0.5 * float(AAL_PI);
  float u = (apertureRad - lightRadiusRad) / (apertureRad + lightRadiusRad);
  float uMax = (halfPi - lightRadiusRad) / (halfPi + lightRadiusRad);
  float w = u > 0.0 ? sqrt(u / uMax) : -sqrt(-u);
  return 0.5 + 0.5 * w;
}

// Isect(aperture, light) in sr from the table (R32F, AAL_CAP_TABLE_WIDTH x
// AAL_CAP_TABLE_HEIGHT, linear filter, clamp to edge): one fetch, no trig
// beyond the smaller cap's area.
float capIntersectionTable(sampler2D table, float apertureRad, float lightRadiusRad, float dRad) {
  const float pi = float(AAL_PI);
  float rs = lightRadiusRad;
  float ra = clamp(apertureRad, 0.0, pi);
  float d = clamp(dRad, 0.0, pi);
  // Beyond a hemisphere: the sun less its part in the complement cap.
  bool flip = ra > 0.5 * pi;
  ra = flip ? pi - ra : ra;
  d = flip ? pi - d : d;
  float smaller = min(ra, rs);
  float t = (d - abs(ra - rs)) / (2.0 * max(smaller, 1e-30));
  const vec2 size = vec2(AAL_CAP_TABLE_WIDTH, AAL_CAP_TABLE_HEIGHT);
  vec2 texel = vec2(clamp(t, 0.0, 1.0), clamp(capTableRow(ra, rs), 0.0, 1.0)) * (size - 1.0);
  float g = textureLod(table, (texel + 0.5) / size, 0.0).r;
  float area = capArea(smaller);
  float inside = t <= 0.0 ? area : (t >= 1.0 ? 0.0 : area * g);
  inside = smaller > 0.0 ? inside : 0.0;
  return flip ? capArea(rs) - inside : inside;
}

#endif
