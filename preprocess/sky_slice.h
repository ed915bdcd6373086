// Closed forms for the visible sky in one azimuth slice. docs/design.md §3 step 2.
//
// In the slice of azimuth phi and width dPhi, the sky is visible above the
// elevation theta0 = max(horizon, tangent plane). With solid angle
// cos(theta) dtheta dphi:
//   visible solid angle += dPhi (1 - sin theta0)
//   bent vector         += dPhi (cos phi Ic, sin phi Ic, Is)
//   Ic = pi/4 - theta0/2 - sin(2 theta0)/4,   Is = (1 - sin^2 theta0) / 2
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <numbers>

namespace aal {

// atan(y) for 0 <= y <= 1 to within 3.3e-7 rad (in float; 2.5e-7 exact):
// the odd minimax polynomial of degree 13, fitted for this project by the
// Remez exchange on [0, 1].
// Its coefficients of y^13, y^11, ..., y (Horner order), shared with the
// AVX2 copy (skySliceTermsAvx2 in bake_avx2.cpp).
inline constexpr double kAtanUnitCoefficients[] = {
    0.006811793290873252, -0.033604220565024996, 0.07962367236561659, -0.1323334209557463,
    0.19807815564989179,  -0.3331736805474933,   0.9999961115495709};
inline constexpr double kSliceHalfPi = std::numbers::pi / 2.0;
inline constexpr double kSliceQuarterPi = std::numbers::pi / 4.0;

template <class Real>
inline Real atanUnit(Real y) {
  const Real y2 = y * y;
  Real p = Real(kAtanUnitCoefficients[0]);
  for (size_t i = 1; i < std::size(kAtanUnitCoefficients); ++i) {
    p = Real(kAtanUnitCoefficients[i]) + y2 * p;
  }
  return y * p;
}

// atan(x) to within 2e-6 rad, several times faster than std::atan: reduced
// to |y| <= 1 by atan(x) = pi/2 - atan(1/x), then atanUnit.
template <class Real>
inline Real fastAtan(Real x) {
  constexpr Real kHalfPi = Real(kSliceHalfPi);
  // Branch-free (selects, not jumps): the horizon tangents that reach here
  // change sign and size from texel to texel, so branches mispredict.
  // Both candidates are computed and one is picked, since compilers will not
  // turn a guarded division into a select.
  const Real a = std::abs(x);
  const bool inverted = a > Real(1);
  const Real inverse = Real(1) / std::max(a, Real(1e-30));
  const Real series = atanUnit(inverted ? inverse : a);
  return std::copysign(inverted ? kHalfPi - series : series, x);
}

// The terms one slice adds to a texel's running sums, laid out like an
// aperture-map texel: term[0..2] the unnormalized bent vector (world frame),
// term[3] the visible solid angle in steradians, for the slice whose lowest
// visible elevation has tangent `tanTheta0` (|tanTheta0| < 1e19, where its
// square is finite). Single precision: the sums are floats anyway.
// Measured per texel in a loop over blocks of 32 (this machine): 3.7 ns;
// 4.5 ns with the earlier atan (two divisions), 5.2 ns computing cos theta0
// and 1/|t| from one square root and one division (a longer dependency
// chain), 5.2-7.4 ns with t clamped first (std::min/max or std::clamp).
inline void skySliceTerms(float* term, float tanTheta0, float dPhi, float cosPhiDPhi,
                          float sinPhiDPhi) {
  const float t = tanTheta0;
  const float inv = 1.0f / (1.0f + t * t);  // cos^2 theta0
  const float sinTheta = t * std::sqrt(inv);
  const float theta = fastAtan(t);
  constexpr float kQuarterPi = static_cast<float>(kSliceQuarterPi);
  const float ic = kQuarterPi - 0.5f * theta - 0.5f * t * inv;  // sin(2 theta)/4 = t/(2(1+t^2))
  const float is = 0.5f * inv;
  term[0] = cosPhiDPhi * ic;
  term[1] = sinPhiDPhi * ic;
  term[2] = dPhi * is;
  term[3] = dPhi * (1.0f - sinTheta);
}

// term[3] of skySliceTerms alone, by the same operations (so the same bits):
// the visible solid angle of the slice, for bakes that keep no bent vector.
inline float visibleSliceTerm(float tanTheta0, float dPhi) {
  const float t = tanTheta0;
  const float inv = 1.0f / (1.0f + t * t);
  const float sinTheta = t * std::sqrt(inv);
  return dPhi * (1.0f - sinTheta);
}

}  // namespace aal
