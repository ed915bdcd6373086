// Spherical caps: area, exact and approximate intersection area, the centroid of
// the visible part of a light.
//
// A cap is the set of unit vectors within arc length r of its centre. Radii and
// the distance d between centres are arc lengths in radians, in [0, pi]. Areas
// are solid angles in steradians, in [0, 4 pi].
//
// The GLSL twins live in shaders/caps.glsl; tests/engine/caps_parity_test.cpp
// checks that both agree on lavapipe.
#pragma once

#include <glm/vec3.hpp>

namespace aal {

// Solid angle of a cap of arc radius r: 2 pi (1 - cos r). docs/design.md §2.
double capArea(double radiusRad);

// Exact intersection area of two caps for all r0, r1, d in [0, pi], including
// caps larger than a hemisphere, coincident and antipodal centres and caps that
// together cover the sphere. Equal to the Tovchigrechko & Vakser (2001) form
// of docs/design.md §2, evaluated as sectors minus triangles so that it stays
// accurate for tiny caps (see caps.cpp). Inputs outside [0, pi] are clamped.
double capIntersectionExact(double r0Rad, double r1Rad, double dRad);

// Oat's smoothstep approximation, exactly as SphericalCapIntersectionAreaFast
// in Oat, "Ambient Aperture Lighting", 2006 (single precision, same branch
// order).
float capIntersectionApprox(float r0Rad, float r1Rad, float dRad);

// Direction to the centroid of the part of the light's cap (centre
// lightDir, radius lightRadiusRad) seen through the aperture cap (centre
// bentNormal), for the Lambert term of the visible light. dRad is the angle
// between the centres and visibleFraction the part of the light's cap that
// is visible (Isect / A(r_light)). The visible part is the side of the light
// nearer the bent normal: its centroid is the light's centre when all of it
// is visible and moves towards B by (1 - visibleFraction) * lightRadiusRad,
// reaching the light's edge as the visible sliver vanishes (for a half-cut
// disk the true offset is 4r/3pi = 0.42 r, this gives 0.5 r).
//
// Oat 2006 approximates the centroid by normalize(B + L), which suits lights as
// large as the aperture but not the sun: for a sun wholly inside the aperture
// it evaluates the Lambert term halfway to B (45 degrees off for an open sky
// and the sun at 45 degrees) where the true term is N.L; against the CPU
// reference that bias was a 17 % error on jacksboro (docs/comparison.md).
glm::vec3 visibleLightCentroid(const glm::vec3& bentNormal, const glm::vec3& lightDir, float dRad,
                               float lightRadiusRad, float visibleFraction);

}  // namespace aal
