// Closed forms for the visible sky in one azimuth slice. DESIGN §3 step 2.
//
// In the slice of azimuth phi and width dPhi, the sky is visible above the
// elevation theta0 = max(horizon, tangent plane). With solid angle
// cos(theta) dtheta dphi:
//   visible solid angle += dPhi (1 - sin theta0)
//   bent vector         += dPhi (cos phi Ic, sin phi Ic, Is)
//   Ic = pi/4 - theta0/2 - sin(2 theta0)/4,   Is = (1 - sin^2 theta0) / 2
#pragma once

#include <cmath>

namespace aal {

// Adds the slice whose lowest visible elevation has tangent `tanTheta0` to a
// texel's running sums, laid out like an aperture-map texel so they live in
// the output's own storage: sum[0..2] the unnormalized bent vector (world
// frame), sum[3] the visible solid angle in steradians.
// cosPhiDPhi = cos(phi) * dPhi and sinPhiDPhi = sin(phi) * dPhi.
inline void addSkySlice(float* sum, double tanTheta0, double dPhi, double cosPhiDPhi,
                        double sinPhiDPhi) {
  const double t = tanTheta0;
  const double inv = 1.0 / (1.0 + t * t);  // cos^2 theta0
  const double sinTheta = t * std::sqrt(inv);
  const double theta = std::atan(t);
  constexpr double kQuarterPi = 0.78539816339744830962;
  const double ic = kQuarterPi - 0.5 * theta - 0.5 * t * inv;  // sin(2 theta)/4 = t/(2(1+t^2))
  const double is = 0.5 * inv;
  sum[0] += static_cast<float>(cosPhiDPhi * ic);
  sum[1] += static_cast<float>(sinPhiDPhi * ic);
  sum[2] += static_cast<float>(dPhi * is);
  sum[3] += static_cast<float>(dPhi * (1.0 - sinTheta));
}

}  // namespace aal
