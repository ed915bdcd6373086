#include "aperture/terrain/light/caps.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "aperture/terrain/units.h"

namespace aal {

namespace {

float smoothstep01(float x) {
  const float t = std::clamp(x, 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

}  // namespace

// 2 pi (1 - cos r) written as 4 pi sin^2(r/2): no cancellation for tiny caps.
double capArea(double radiusRad) {
  const double h = std::sin(0.5 * radiusRad);
  return 4.0 * kPi * h * h;
}

double capIntersectionExact(double r0Rad, double r1Rad, double dRad) {
  const double r0 = std::clamp(r0Rad, 0.0, kPi);
  const double r1 = std::clamp(r1Rad, 0.0, kPi);
  const double d = std::clamp(dRad, 0.0, kPi);

  if (d >= r0 + r1) return 0.0;                                  // disjoint
  if (d <= std::abs(r0 - r1)) return capArea(std::min(r0, r1));  // nested
  if (r0 + r1 + d >= 2.0 * kPi) {
    // Together the caps cover the sphere: A(r0) + A(r1) - 4 pi, written with
    // the complement cap 4 pi - A(r1) = A(pi - r1) to avoid cancellation.
    return capArea(r0) - capArea(kPi - r1);
  }

  // Partial overlap. The boundaries meet at P; the triangle C0-C1-P has sides
  // r0, r1, d. The lens is the two cap sectors at C0 and C1 (half-angles a0,
  // a1) minus the triangle and its mirror image (spherical excess E):
  //   area = 2 (1 - cos r0) a0 + 2 (1 - cos r1) a1 - 2 E.
  // By Girard's theorem this equals the Tovchigrechko & Vakser form of
  // docs/design.md §2, but half-angle and L'Huilier formulas keep it accurate
  // for tiny caps (the sun) and near every branch boundary, where acos loses
  // half the digits.
  const double s = 0.5 * (r0 + r1 + d);
  const double sinS = std::sin(s), sinS0 = std::sin(s - r0), sinS1 = std::sin(s - r1),
               sinSd = std::sin(s - d);
  const double a0 = 2.0 * std::atan2(std::sqrt(sinS0 * sinSd), std::sqrt(sinS * sinS1));
  const double a1 = 2.0 * std::atan2(std::sqrt(sinS1 * sinSd), std::sqrt(sinS * sinS0));
  const double excess =
      4.0 * std::atan(std::sqrt(std::tan(0.5 * s) * std::tan(0.5 * (s - r0)) *
                                std::tan(0.5 * (s - r1)) * std::tan(0.5 * (s - d))));
  const double h0 = std::sin(0.5 * r0), h1 = std::sin(0.5 * r1);  // 1 - cos r = 2 sin^2(r/2)
  const double area = 4.0 * h0 * h0 * a0 + 4.0 * h1 * h1 * a1 - 2.0 * excess;
  // Rounding can step a hair outside the valid range.
  return std::clamp(area, 0.0, capArea(std::min(r0, r1)));
}

float capIntersectionApprox(float r0Rad, float r1Rad, float dRad) {
  constexpr float kTwoPi = 6.283185308f;  // the constant of Oat's listing
  const float smaller = std::min(r0Rad, r1Rad);
  if (dRad <= std::max(r0Rad, r1Rad) - smaller) {
    return kTwoPi - kTwoPi * std::cos(smaller);  // one cap inside the other
  }
  if (dRad >= r0Rad + r1Rad) return 0.0f;  // no intersection
  const float diff = std::abs(r0Rad - r1Rad);
  const float overlap = std::clamp((dRad - diff) / (r0Rad + r1Rad - diff), 0.0f, 1.0f);
  return smoothstep01(1.0f - overlap) * (kTwoPi - kTwoPi * std::cos(smaller));
}

glm::vec3 visibleLightCentroid(const glm::vec3& bentNormal, const glm::vec3& lightDir, float dRad,
                               float lightRadiusRad, float visibleFraction) {
  const float shift =
      std::min(dRad, (1.0f - std::clamp(visibleFraction, 0.0f, 1.0f)) * lightRadiusRad);
  const glm::vec3 across = bentNormal - lightDir * glm::dot(bentNormal, lightDir);
  const float length = glm::length(across);
  if (shift <= 0.0f || length < 1e-7f) return lightDir;  // centred, or nothing to lean to
  return lightDir * std::cos(shift) + across / length * std::sin(shift);
}

}  // namespace aal
