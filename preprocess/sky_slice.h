// Closed forms for the visible sky in one azimuth slice. DESIGN §3 step 2.
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

namespace aal {

// atan(x) to within 2e-6 rad, several times faster than std::atan: reduced
// to |y| <= tan(pi/8) by atan(x) = pi/2 - atan(1/x) and atan(x) = pi/4 +
// atan((x - 1)/(x + 1)), then the Taylor series to y^11 (next term < 1.1e-6).
template <class Real>
inline Real fastAtan(Real x) {
  constexpr Real kHalfPi = Real(1.57079632679489661923), kQuarterPi = Real(0.78539816339744830962);
  constexpr Real kTanEighthPi = Real(0.41421356237309504880);
  // Branch-free (selects, not jumps): the horizon tangents that reach here
  // change sign and size from texel to texel, so branches mispredict.
  // Both candidates are computed and one is picked, since compilers will not
  // turn a guarded division into a select.
  const Real a = std::abs(x);
  const bool inverted = a > Real(1);
  const Real inverse = Real(1) / std::max(a, Real(1e-30));
  const Real reduced = inverted ? inverse : a;
  const bool shifted = reduced > kTanEighthPi;
  const Real folded = (reduced - Real(1)) / (reduced + Real(1));
  const Real y = shifted ? folded : reduced;
  const Real y2 = y * y;
  const Real series =
      y * (Real(1) + y2 * (Real(-1.0 / 3) +
                           y2 * (Real(1.0 / 5) +
                                 y2 * (Real(-1.0 / 7) + y2 * (Real(1.0 / 9) - y2 / Real(11))))));
  const Real base = shifted ? kQuarterPi : Real(0);
  const Real result = inverted ? kHalfPi - (base + series) : base + series;
  return std::copysign(result, x);
}

// The terms one slice adds to a texel's running sums, laid out like an
// aperture-map texel: term[0..2] the unnormalized bent vector (world frame),
// term[3] the visible solid angle in steradians, for the slice whose lowest
// visible elevation has tangent `tanTheta0`. Single precision: the sums are
// floats anyway.
inline void skySliceTerms(float* term, float tanTheta0, float dPhi, float cosPhiDPhi,
                          float sinPhiDPhi) {
  const float t = tanTheta0;
  const float inv = 1.0f / (1.0f + t * t);  // cos^2 theta0
  const float sinTheta = t * std::sqrt(inv);
  const float theta = fastAtan(t);
  constexpr float kQuarterPi = 0.78539816339744830962f;
  const float ic = kQuarterPi - 0.5f * theta - 0.5f * t * inv;  // sin(2 theta)/4 = t/(2(1+t^2))
  const float is = 0.5f * inv;
  term[0] = cosPhiDPhi * ic;
  term[1] = sinPhiDPhi * ic;
  term[2] = dPhi * is;
  term[3] = dPhi * (1.0f - sinTheta);
}

}  // namespace aal
