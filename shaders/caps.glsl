// Spherical caps in GLSL: twins of terrain/light/caps.h (see there for the contract).
// Radii and distances are arc lengths in radians; areas in steradians.
#ifndef AAL_CAPS_GLSL
#define AAL_CAPS_GLSL

#include "config.h"

// 2 pi (1 - cos r) as 4 pi sin^2(r/2): no cancellation for tiny caps (the sun).
// Angle (rad) between two unit directions, the centres of two caps, as
// atan2(|a x b|, a.b): GPU acos approximations are too coarse at the sun's
// scale (lavapipe's was off by ~1e-3 rad).
float capCentreDistance(vec3 a, vec3 b) {
  return atan(length(cross(a, b)), dot(a, b));
}

float capArea(float radiusRad) {
  float h = sin(0.5 * radiusRad);
  return 2.0 * float(AAL_TWO_PI) * h * h;
}

// Exact intersection area, docs/design.md §2.
float capIntersectionExact(float r0Rad, float r1Rad, float dRad) {
  const float pi = float(AAL_PI);
  float r0 = clamp(r0Rad, 0.0, pi);
  float r1 = clamp(r1Rad, 0.0, pi);
  float d = clamp(dRad, 0.0, pi);

  if (d >= r0 + r1) return 0.0;
  if (d <= abs(r0 - r1)) return capArea(min(r0, r1));
  if (r0 + r1 + d >= 2.0 * pi) return capArea(r0) - capArea(pi - r1);  // A0 + A1 - 4 pi

  // Sectors minus triangles, as terrain/light/caps.cpp explains.
  float s = 0.5 * (r0 + r1 + d);
  float sinS = sin(s), sinS0 = sin(s - r0), sinS1 = sin(s - r1), sinSd = sin(s - d);
  float a0 = 2.0 * atan(sqrt(sinS0 * sinSd), sqrt(sinS * sinS1));
  float a1 = 2.0 * atan(sqrt(sinS1 * sinSd), sqrt(sinS * sinS0));
  float excess = 4.0 * atan(sqrt(tan(0.5 * s) * tan(0.5 * (s - r0)) * tan(0.5 * (s - r1)) *
                                 tan(0.5 * (s - d))));
  float h0 = sin(0.5 * r0), h1 = sin(0.5 * r1);
  float area = 4.0 * h0 * h0 * a0 + 4.0 * h1 * h1 * a1 - 2.0 * excess;
  return clamp(area, 0.0, capArea(min(r0, r1)));
}

// SphericalCapIntersectionAreaFast of Oat, "Ambient Aperture Lighting", 2006,
// same branch order.
float capIntersectionApprox(float r0Rad, float r1Rad, float dRad) {
  const float twoPi = 6.283185308;
  float smaller = min(r0Rad, r1Rad);
  if (dRad <= max(r0Rad, r1Rad) - smaller) return twoPi - twoPi * cos(smaller);
  if (dRad >= r0Rad + r1Rad) return 0.0;
  float diff = abs(r0Rad - r1Rad);
  float overlap = clamp((dRad - diff) / (r0Rad + r1Rad - diff), 0.0, 1.0);
  return smoothstep(0.0, 1.0, 1.0 - overlap) * (twoPi - twoPi * cos(smaller));
}

// Centroid of the visible part of the light's cap: twin of
// visibleLightCentroid in terrain/light/caps.h (see there).
vec3 visibleLightCentroid(vec3 bentNormal, vec3 lightDir, float dRad, float lightRadiusRad,
                          float visibleFraction) {
  float shift = min(dRad, (1.0 - clamp(visibleFraction, 0.0, 1.0)) * lightRadiusRad);
  vec3 across = bentNormal - lightDir * dot(bentNormal, lightDir);
  float len = length(across);
  if (shift <= 0.0 || len < 1e-7) return lightDir;
  return lightDir * cos(shift) + across / len * sin(shift);
}

#endif
