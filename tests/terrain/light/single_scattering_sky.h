// A slow, spectral reference for the colour of a clear sky: single
// scattering of sunlight by air (Rayleigh) and aerosol (Mie) along view rays
// in a spherical atmosphere of exponential density, after Nishita, Sirai,
// Tadamura & Nakamae 1993, "Display of the Earth Taking into Account
// Atmospheric Scattering" (SIGGRAPH 93). Used by tests/terrain/light/sky_model_test.cpp
// to see what colour the sky near the horizon has under a midday sun
// (docs/sun-and-sky.md, "Sky colour near the horizon").
//
// Model, per wavelength 380-780 nm in 5 nm steps:
//   L(v) = integral over the view ray of
//          E_sun T(p -> sun) [b_R(h) P_R(mu) + w b_A(h) P_A(mu)] T(eye -> p) ds
// - air: vertical optical depth tau_R = 0.008735 lambda^-4.08 (lambda in um;
//   Leckner 1978, as terrain/light/atmosphere.h), scale height 8 km, phase
//   3/(16 pi) (1 + mu²);
// - aerosol: tau_A = beta lambda^-1.3 with Preetham's beta(T) = 0.04608 T -
//   0.04586 (as terrain/light/atmosphere.h), scale height 1.2 km, single-scattering
//   albedo 0.9, the phase function of Cornette & Shanks 1992, "Physically
//   reasonable analytic expression for the single-scattering phase
//   function" (Applied Optics 31(16)), with g = 0.76;
// - Earth radius 6371 km, atmosphere 100 km deep, eye 1 m above the ground,
//   no ozone, no multiple scattering, no ground reflection;
// - sun: a 5772 K black body (IAU 2015 nominal solar effective temperature),
//   the result white-balanced to it: a Bradford transform (Lam 1985,
//   "Metamerism and colour constancy", thesis, University of Bradford) maps
//   the sun's white to D65, as the renderer takes the extraterrestrial sun
//   for white (docs/sun-and-sky.md, "Units");
// - colour matching: the CIE 1931 2° observer as the multi-lobe Gaussian fit
//   of Wyman, Sloan & Shirley 2013, "Simple Analytic Approximations to the
//   CIE XYZ Color Matching Functions" (JCGT 2(2)).
// Integration: midpoint rule, samples spaced quadratically along each ray
// (dense near the eye, where the air is dense for low views).
#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace aal::test {

struct ClearAtmosphere {
  double turbidity = 2.5;  // Preetham's T, sets the aerosol optical depth
  bool aerosol = true;     // false: air alone (a Rayleigh sky)
  int viewSteps = 400;     // samples along the view ray
  int sunSteps = 100;      // samples along each ray towards the sun
};

// CIE 1931 colour matching functions (x̄, ȳ, z̄) at wavelength nm (Wyman et al. 2013).
glm::dvec3 colourMatching(double wavelengthNm);

// Planck's spectral radiance at wavelength nm and temperature K, up to a constant factor.
double blackBody(double wavelengthNm, double temperatureK);

// CIE XYZ (relative units, white-balanced as in the file comment) of the
// clear sky seen from the ground along unit viewDir (z up, above the
// horizon) with the sun in unit direction sunDir (above the horizon).
glm::dvec3 singleScatteringSkyXyz(const glm::dvec3& sunDir, const glm::dvec3& viewDir,
                                  const ClearAtmosphere& atmosphere);

// (x, y) of XYZ.
glm::dvec2 chromaticity(const glm::dvec3& xyz);

// Correlated colour temperature (K) of chromaticity xy, McCamy 1992,
// "Correlated color temperature as an explicit function of chromaticity
// coordinates" (Color Res. Appl. 17(2)): within a few K of the exact CCT
// from 2850 K to 6500 K, within ~1% to 10 000 K.
double correlatedColourTemperature(const glm::dvec2& xy);

}  // namespace aal::test
