// The exact intersection of an aperture cap with the sun's cap as a table:
// the sun's radius is fixed within a frame, so the area is a function of two
// variables, the aperture's arc length r_a and the angle d between the bent
// normal and the sun. `exact` shading fetches it (shaders/cap_table.glsl, one
// bilinear fetch) instead of evaluating capIntersectionExact (terrain/light/caps.h,
// which stays the reference). Layout and accuracy: docs/caps.md.
//
// Parametrisation (r_s the sun's radius, m = min(r_a, r_s)):
// - apertures beyond a hemisphere go through their complement: the sun's part
//   inside the cap (r_a, d) is A(r_s) minus its part inside the cap
//   (pi - r_a, pi - d) around -B, so the table covers r_a in [0, pi/2];
// - across: t = (d - |r_a - r_s|) / 2m, the position in the band where the
//   area changes (t <= 0: one cap inside the other, A(m); t >= 1: disjoint,
//   0; Oat's smoothstep runs over the same band). The stored value is
//   g = Isect / A(m) in [0, 1]. Scaling the band by m keeps the thin sun's
//   transition, 2 r_s = 0.5 degrees wide, as many texels wide as any;
// - down: w = sign(u) sqrt(|u| / u_max) with u = (r_a - r_s) / (r_a + r_s),
//   u_max its value at pi/2, row s = (1 + w) / 2: r_a = 0 at s = 0, r_a = r_s
//   at s = 1/2 (a row), pi/2 at s = 1. Where r_a = r_s and t = 0 the two
//   caps coincide and g has a corner (the loss grows as t^(3/2) for unequal
//   caps, as t for equal ones); the square root crowds rows there.
#pragma once

#include <vector>

namespace aal {

// The row coordinate s in [0, 1] of aperture arc length apertureRad in
// [0, pi/2] for a light of radius lightRadiusRad in (0, pi/2).
float capTableRow(float apertureRad, float lightRadiusRad);
// Its inverse: the aperture arc length of row coordinate s.
double capTableAperture(double s, double lightRadiusRad);

struct CapIntersectionTable {
  float lightRadiusRad = 0;
  // AAL_CAP_TABLE_HEIGHT rows (s = row / (height - 1)) of AAL_CAP_TABLE_WIDTH
  // values (t = column / (width - 1)): g = Isect / A(min(r_a, r_s)).
  std::vector<float> values;
};

// Tabulates capIntersectionExact for a light of radius lightRadiusRad in
// (0, pi/2). About 17 000 closed-form evaluations (a few ms).
CapIntersectionTable makeCapIntersectionTable(float lightRadiusRad);

// Intersection area (sr) of the aperture cap (apertureRad, any in [0, pi])
// with the table's light dRad away, read from the table with bilinear
// interpolation: the C++ twin of capIntersectionTable in
// shaders/cap_table.glsl (single precision, same steps).
float capIntersectionFromTable(const CapIntersectionTable& table, float apertureRad, float dRad);

}  // namespace aal
