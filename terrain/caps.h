// Spherical caps: area, exact and approximate intersection area, Lambert centroid.
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

// Solid angle of a cap of arc radius r: 2 pi (1 - cos r). DESIGN §2.
double capArea(double radiusRad);

// Exact intersection area of two caps for all r0, r1, d in [0, pi], including
// caps larger than a hemisphere, coincident and antipodal centres and caps that
// together cover the sphere. Equal to the Tovchigrechko & Vakser (2001) form
// of DESIGN §2, evaluated as sectors minus triangles so that it stays
// accurate for tiny caps (see caps.cpp). Inputs outside [0, pi] are clamped.
double capIntersectionExact(double r0Rad, double r1Rad, double dRad);

// Oat's smoothstep approximation, exactly as SphericalCapIntersectionAreaFast
// in seed 002 (single precision, same branch order).
float capIntersectionApprox(float r0Rad, float r1Rad, float dRad);

// Direction to the centroid of the intersection of the aperture cap (centre
// bentNormal) and the light cap (centre lightDir), approximated by
// normalize(B + L) (seed 002, "Don't forget about our friend Lambert").
// Both inputs are unit vectors; when they are opposite the bent normal is
// returned (the caps cannot intersect then unless one covers the sphere).
glm::vec3 lambertCentroid(const glm::vec3& bentNormal, const glm::vec3& lightDir);

}  // namespace aal
