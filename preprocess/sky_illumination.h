// Diffuse sky illumination and the anisotropic sky-view factor from the
// bake's horizon sweeps. docs/baking.md, "Sky illumination" and
// "Anisotropic sky-view factor".
//
// Sky illumination: the irradiance of a texel from a sky of radiance L(e)
// (e the elevation), over the directions above the local horizontal, above
// the terrain's horizon and in front of the texel's tangent plane, divided
// by the irradiance of a horizontal plane under the whole sky (1 there).
// Per sweep azimuth phi the visible sky is the elevations [e0, 90°], e0 =
// max(0, horizon, tangent plane), and the integral over them is closed form:
// with n = (-sx, -sy, 1) / N the unit normal (N = sqrt(1 + sx² + sy²)) and
// p = sx cos phi + sy sin phi the tangent of the tangent plane's elevation,
// n · w = (sin e - p cos e) / N and dw = cos e de dphi.
#pragma once

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/sky_slice.h"

namespace aal {

enum class SkyModel {
  Uniform,   // L constant
  Overcast,  // CIE standard overcast sky (Moon & Spencer 1942): L ∝ (1 + 2 sin e) / 3
};

// The integral over e in [e0, 90°] of L(e) (sin e - p cos e) cos e, L
// without its constant; e0 given by its tangent t0 >= 0 and p the tangent
// plane's tangent in the slice's azimuth (t0 >= p). Uniform:
//   ∫ sin e cos e = cos² e0 / 2,  ∫ cos² e = (pi/2 - e0 - sin e0 cos e0) / 2.
// Overcast, L = 1 + 2 sin e, adds twice the same weighted by sin e:
//   ∫ sin² e cos e = (1 - sin³ e0) / 3,  ∫ sin e cos² e = cos³ e0 / 3.
// The integrand is >= 0 for e >= e0 >= the plane's elevation; the max
// guards the rounding.
inline float skyIlluminationSlice(float t0, float p, SkyModel model) {
  constexpr float kHalfPi = float(std::numbers::pi / 2);
  const float c = 1.0f / std::sqrt(1.0f + t0 * t0), s = t0 * c;
  const float e0 = fastAtan(t0);
  float up = 0.5f * c * c;                     // ∫ sin e cos e
  float side = 0.5f * (kHalfPi - e0 - s * c);  // ∫ cos² e
  if (model == SkyModel::Overcast) {
    up += (2.0f / 3.0f) * (1.0f - s * s * s);
    side += (2.0f / 3.0f) * c * c * c;
  }
  return std::max(0.0f, up - p * side);
}

// The sums of skyIlluminationSlice over `azimuths` evenly spaced azimuths
// to the illumination, in place: times the slice width 2 pi / azimuths, over
// N and the horizontal plane's integral (uniform: pi; overcast: 7 pi / 9 for
// L = (1 + 2 sin e) / 3, here without the 1/3: 7 pi / 3).
void finishSkyIllumination(const BakeTerrain& terrain, std::vector<float>& sums, int azimuths,
                           SkyModel model);

// The anisotropic sky-view factor's weights (Zakšek, Oštir & Kokalj 2011 as
// RVT computes it): w = (1 - minWeight) cos((A - mainDirection) / 2)^exponent
// + minWeight, A the azimuth of the slice clockwise from north.
struct Anisotropy {
  double mainDirectionDeg = 315;  // clockwise from north, as RVT
  int exponent = 4;               // RVT's "low" level; "high": 8
  double minWeight = 0.4;         // RVT's "low" level; "high": 0.1
};

// RVT's two levels.
inline Anisotropy anisotropyLevel(bool high, double mainDirectionDeg) {
  return high ? Anisotropy{mainDirectionDeg, 8, 0.1} : Anisotropy{mainDirectionDeg, 4, 0.4};
}

// The weight of the sweep azimuth phi (radians, counter-clockwise from east).
inline double anisotropicWeight(const Anisotropy& a, double phi) {
  const double azimuthFromNorth = std::numbers::pi / 2 - phi;
  const double half = 0.5 * (azimuthFromNorth - a.mainDirectionDeg * std::numbers::pi / 180);
  return (1 - a.minWeight) * std::pow(std::cos(half), a.exponent) + a.minWeight;
}

}  // namespace aal
