// Sunlight through a clear atmosphere: air mass, transmittance, and the sun's
// irradiance at the ground in the renderer's photometric RGB.
//
// Photometric RGB (shared with sky_model.h and tone_map.h): linear Rec. 709 /
// sRGB primaries with a D65 white, scaled so that the luminance
// Y = 0.2126 R + 0.7152 G + 0.0722 B is in photometric units with a factor
// 1000: irradiances are in kilolux (klx), radiances in kilocandela per square
// metre (kcd/m², "kilonits"). A white Lambertian surface under an irradiance E
// has radiance E / pi in these units. Clear-day reference values: direct sun
// about 100 klx at normal incidence, diffuse sky 10-25 klx on a horizontal
// surface, zenith sky a few kcd/m².
//
// Spectral model: the three channels are sampled at single wavelengths
// (680, 550, 440 nm), each attenuated by Beer-Lambert along the relative air
// mass m with the vertical optical depths of
//   Rayleigh scattering   tau_R = 0.008735 lambda^-4.08     (lambda in um; Leckner 1978,
//                                                           as in Preetham et al. 1999 App. A.2)
//   aerosol (Angstrom)    tau_a = beta lambda^-alpha, alpha = 1.3,
//                         beta = 0.04608 T - 0.04586        (Preetham et al. 1999 App. A.2,
//                                                           T = turbidity as in the sky model)
//   ozone                 tau_o = k_o(lambda) l, l = 0.35 cm (STP column)
//                         k_o = sigma(lambda) N_L, sigma the ozone cross-section
//                         (Serdyuchenko et al. 2014, 293 K) and N_L = 2.687e19 cm^-3
//                         (Loschmidt): k_o = 0.0325, 0.0940, 0.00425 cm^-1.
// Water vapour and mixed-gas absorption bands (Preetham App. A.2) are left out:
// they lie mostly outside the three sample wavelengths. The extraterrestrial
// sun is taken as the white point: RGB (1, 1, 1) times the solar illuminance
// constant (its true ~5800 K colour is a slight warm tint that a camera's
// white balance removes).
#pragma once

#include <glm/vec3.hpp>

#include "aperture/terrain/units.h"

namespace aal {

// Solar illuminance constant at 1 AU: 133.3 klx (Darula, Kittler & Gueymard
// 2005, "Reference luminous solar constant and solar luminance for
// illuminance calculations", Solar Energy 79).
constexpr double kSolarIlluminanceKlx = 133.334;

// Default atmospheric turbidity (Preetham's T: 2 very clear, 3 clear, 6 hazy).
constexpr double kDefaultTurbidity = 2.5;

// Default total ozone column, cm at STP (350 Dobson units; Preetham App. A.2).
constexpr double kDefaultOzoneCm = 0.35;

// Wavelengths at which the R, G, B channels are sampled, nanometres.
constexpr double kChannelWavelengthNm[3] = {680.0, 550.0, 440.0};

// Relative optical air mass for an apparent (refracted) elevation in degrees,
// Kasten & Young 1989 ("Revised optical air mass tables and approximation
// formula", Applied Optics 28(22), eq. 3):
//   m = 1 / (cos z + 0.50572 (96.07995 - z)^-1.6364),  z = 90 - elevation, degrees.
// 1 at the zenith, ~38 at the horizon. Elevations are clamped to [0, 90].
double relativeAirMass(double elevationDeg);

// Angstrom turbidity coefficient beta for turbidity T (Preetham et al. 1999,
// App. A.2): 0.04608 T - 0.04586, clamped at 0 (T < ~1).
double angstromBeta(double turbidity);

// Vertical (air mass 1) optical depth at the three channel wavelengths:
// Rayleigh + aerosol + ozone as in the file comment. turbidity >= 1,
// ozoneCm >= 0.
glm::vec3 verticalOpticalDepth(double turbidity, double ozoneCm = kDefaultOzoneCm);

// Direct-beam transmittance exp(-m tau) per channel for air mass m >= 1, in (0, 1].
glm::vec3 directTransmittance(double airMass, double turbidity, double ozoneCm = kDefaultOzoneCm);

// Fraction in [0, 1] of the sun's disk above a flat horizon when its centre is
// at elevationDeg: the area of the circular segment above the horizon line
// over the disk's area (1 at elevation >= r, 1/2 at 0, 0 at <= -r).
double sunDiskVisibleFraction(double elevationDeg, double sunRadiusDeg = kSunAngularRadiusDeg);

// Irradiance of the sun's direct beam at normal incidence at the ground, in
// photometric RGB (klx; see the file comment):
//   kSolarIlluminanceKlx / distance^2 * directTransmittance(m(elevation)) * disk fraction.
// elevationDeg is the apparent elevation (SolarPosition::elevationDeg); the air
// mass uses max(elevation, 0), and the beam fades out with the part of the
// disk above the horizon, reaching 0 at elevation -sunRadiusDeg.
// Examples at T = 2.5: ~(113, 100, 85) klx at 90°, warm red ~(5, 0.5, 0.02) at 2°.
glm::vec3 sunIrradiance(double elevationDeg, double turbidity = kDefaultTurbidity,
                        double sunDistanceAu = 1.0, double sunRadiusDeg = kSunAngularRadiusDeg,
                        double ozoneCm = kDefaultOzoneCm);

// Luminance of a photometric RGB value: 0.2126 R + 0.7152 G + 0.0722 B
// (Rec. 709 / sRGB Y row), in the same unit (klx or kcd/m²).
float luminance(const glm::vec3& rgb);

}  // namespace aal
