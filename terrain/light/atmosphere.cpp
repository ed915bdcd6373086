#include "aperture/terrain/light/atmosphere.h"

#include <algorithm>
#include <cmath>

#include "aperture/terrain/units.h"

namespace aal {

namespace {

// Ozone absorption coefficients k_o = sigma N_L at 680, 550, 440 nm, cm^-1
// (see atmosphere.h: Serdyuchenko et al. 2014 cross-sections 1.209e-21,
// 3.500e-21, 1.582e-22 cm^2 times Loschmidt's number 2.687e19 cm^-3).
constexpr double kOzoneAbsorptionPerCm[3] = {0.0325, 0.0940, 0.00425};

constexpr double kAngstromAlpha = 1.3;  // Preetham et al. 1999, App. A.2

}  // namespace

double relativeAirMass(double elevationDeg) {
  const double zenithDeg = 90.0 - std::clamp(elevationDeg, 0.0, 90.0);
  return 1.0 / (std::cos(radians(zenithDeg)) + 0.50572 * std::pow(96.07995 - zenithDeg, -1.6364));
}

double angstromBeta(double turbidity) {
  return std::max(0.0, 0.04608 * turbidity - 0.04586);
}

glm::vec3 verticalOpticalDepth(double turbidity, double ozoneCm) {
  const double beta = angstromBeta(turbidity);
  glm::vec3 tau;
  for (int c = 0; c < 3; ++c) {
    const double lambdaUm = kChannelWavelengthNm[c] / 1000.0;
    const double rayleigh = 0.008735 * std::pow(lambdaUm, -4.08);
    const double aerosol = beta * std::pow(lambdaUm, -kAngstromAlpha);
    const double ozone = kOzoneAbsorptionPerCm[c] * std::max(0.0, ozoneCm);
    tau[c] = static_cast<float>(rayleigh + aerosol + ozone);
  }
  return tau;
}

glm::vec3 directTransmittance(double airMass, double turbidity, double ozoneCm) {
  const glm::vec3 tau = verticalOpticalDepth(turbidity, ozoneCm);
  glm::vec3 t;
  for (int c = 0; c < 3; ++c) t[c] = static_cast<float>(std::exp(-airMass * double(tau[c])));
  return t;
}

double sunDiskVisibleFraction(double elevationDeg, double sunRadiusDeg) {
  if (sunRadiusDeg <= 0.0) return elevationDeg >= 0.0 ? 1.0 : 0.0;
  // Centre height h in disk radii; area of the unit disk above y = -h is
  // acos(-h) + h sqrt(1 - h^2) (circular segment), out of pi.
  const double h = std::clamp(elevationDeg / sunRadiusDeg, -1.0, 1.0);
  return std::clamp((std::acos(-h) + h * std::sqrt(1.0 - h * h)) / kPi, 0.0, 1.0);
}

glm::vec3 sunIrradiance(double elevationDeg, double turbidity, double sunDistanceAu,
                        double sunRadiusDeg, double ozoneCm) {
  const double visible = sunDiskVisibleFraction(elevationDeg, sunRadiusDeg);
  if (visible <= 0.0) return glm::vec3(0.0f);
  const double distance = sunDistanceAu > 0.0 ? sunDistanceAu : 1.0;
  const double scale = kSolarIlluminanceKlx / (distance * distance) * visible;
  return static_cast<float>(scale) *
         directTransmittance(relativeAirMass(elevationDeg), turbidity, ozoneCm);
}

float luminance(const glm::vec3& rgb) {
  return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

}  // namespace aal
