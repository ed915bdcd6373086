#include "aperture/tests/terrain/light/single_scattering_sky.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>

namespace aal::test {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kEarthRadiusM = 6371e3;
constexpr double kAtmosphereTopM = kEarthRadiusM + 100e3;
constexpr double kAirScaleHeightM = 8000.0;
constexpr double kAerosolScaleHeightM = 1200.0;
constexpr double kAerosolAlbedo = 0.9;
constexpr double kAerosolAsymmetry = 0.76;
constexpr double kSunTemperatureK = 5772.0;

// One lobe of Wyman et al.'s fit: a Gaussian with different widths either side.
double lobe(double nm, double mean, double sigmaBelow, double sigmaAbove) {
  const double t = (nm - mean) / (nm < mean ? sigmaBelow : sigmaAbove);
  return std::exp(-0.5 * t * t);
}

// Distance from p along unit d to where the ray leaves the sphere of radius r
// around the Earth's centre (p inside it).
double distanceToSphere(const glm::dvec3& p, const glm::dvec3& d, double r) {
  const double b = glm::dot(p, d), c = glm::dot(p, p) - r * r;
  return -b + std::sqrt(std::max(0.0, b * b - c));
}

// Relative densities (air, aerosol) at p: exp(-height / scale height).
glm::dvec2 densities(const glm::dvec3& p) {
  const double h = glm::length(p) - kEarthRadiusM;
  return {std::exp(-h / kAirScaleHeightM), std::exp(-h / kAerosolScaleHeightM)};
}

// Sample i of n along a ray of `length`: midpoint distance and step, spaced
// quadratically (s = length u², u uniform).
void sample(int i, int n, double length, double& s, double& ds) {
  const double u0 = double(i) / n, u1 = double(i + 1) / n, um = 0.5 * (u0 + u1);
  s = length * um * um;
  ds = length * (u1 * u1 - u0 * u0);
}

// Integral of the densities (metres at sea-level density) from p towards the
// sun out of the atmosphere; infinite where the Earth is in the way.
glm::dvec2 columnToSun(const glm::dvec3& p, const glm::dvec3& sun, int steps) {
  const double b = glm::dot(p, sun), c = glm::dot(p, p) - kEarthRadiusM * kEarthRadiusM;
  if (b < 0.0 && b * b - c > 0.0) return glm::dvec2(INFINITY);
  const double length = distanceToSphere(p, sun, kAtmosphereTopM);
  glm::dvec2 column(0.0);
  for (int i = 0; i < steps; ++i) {
    double s, ds;
    sample(i, steps, length, s, ds);
    column += densities(p + s * sun) * ds;
  }
  return column;
}

// Bradford cone response matrix (Lam 1985; rows).
const glm::dmat3 kBradford = glm::transpose(glm::dmat3(0.8951, 0.2664, -0.1614,  //
                                                       -0.7502, 1.7135, 0.0367,  //
                                                       0.0389, -0.0685, 1.0296));

}  // namespace

glm::dvec3 colourMatching(double nm) {
  return {1.056 * lobe(nm, 599.8, 37.9, 31.0) + 0.362 * lobe(nm, 442.0, 16.0, 26.7) -
              0.065 * lobe(nm, 501.1, 20.4, 26.2),
          0.821 * lobe(nm, 568.8, 46.9, 40.5) + 0.286 * lobe(nm, 530.9, 16.3, 31.1),
          1.217 * lobe(nm, 437.0, 11.8, 36.0) + 0.681 * lobe(nm, 459.0, 26.0, 13.8)};
}

double blackBody(double nm, double kelvin) {
  constexpr double kC2 = 1.438777e-2;  // second radiation constant, m K
  const double metres = nm * 1e-9;
  return 1.0 / (std::pow(metres, 5.0) * std::expm1(kC2 / (metres * kelvin)));
}

glm::dvec3 singleScatteringSkyXyz(const glm::dvec3& sunDir, const glm::dvec3& viewDir,
                                  const ClearAtmosphere& a) {
  const glm::dvec3 sun = glm::normalize(sunDir), view = glm::normalize(viewDir);
  constexpr int kWavelengths = 81;  // 380, 385, ..., 780 nm
  double airDepth[kWavelengths], aerosolDepth[kWavelengths];
  glm::dvec3 sunXyz[kWavelengths], sunWhite(0.0);
  const double beta = 0.04608 * a.turbidity - 0.04586;  // Preetham App. A.2
  for (int k = 0; k < kWavelengths; ++k) {
    const double nm = 380.0 + 5.0 * k, um = nm / 1000.0;
    airDepth[k] = 0.008735 * std::pow(um, -4.08);
    aerosolDepth[k] = a.aerosol ? beta * std::pow(um, -1.3) : 0.0;
    sunXyz[k] = colourMatching(nm) * blackBody(nm, kSunTemperatureK);
    sunWhite += sunXyz[k];
  }
  const double mu = glm::dot(sun, view), g = kAerosolAsymmetry;
  const double airPhase = 3.0 / (16.0 * kPi) * (1.0 + mu * mu);
  const double aerosolPhase = 3.0 / (8.0 * kPi) * (1.0 - g * g) * (1.0 + mu * mu) /
                              ((2.0 + g * g) * std::pow(1.0 + g * g - 2.0 * g * mu, 1.5));

  const glm::dvec3 eye(0.0, 0.0, kEarthRadiusM + 1.0);
  const double length = distanceToSphere(eye, view, kAtmosphereTopM);
  glm::dvec3 xyz(0.0);
  glm::dvec2 columnFromEye(0.0);
  for (int i = 0; i < a.viewSteps; ++i) {
    double s, ds;
    sample(i, a.viewSteps, length, s, ds);
    const glm::dvec3 p = eye + s * view;
    const glm::dvec2 density = densities(p);
    const glm::dvec2 column = columnFromEye + 0.5 * ds * density + columnToSun(p, sun, a.sunSteps);
    columnFromEye += ds * density;
    if (!std::isfinite(column.x)) continue;  // in the Earth's shadow
    for (int k = 0; k < kWavelengths; ++k) {
      const double airPerM = airDepth[k] / kAirScaleHeightM;
      const double aerosolPerM = aerosolDepth[k] / kAerosolScaleHeightM;
      const double scattering =
          airPerM * density.x * airPhase + kAerosolAlbedo * aerosolPerM * density.y * aerosolPhase;
      xyz +=
          sunXyz[k] * (std::exp(-(airPerM * column.x + aerosolPerM * column.y)) * scattering * ds);
    }
  }
  // White balance: the sun's own chromaticity becomes D65's (Bradford).
  const glm::dvec3 d65(0.95047, 1.0, 1.08883);
  const glm::dvec3 from = kBradford * (sunWhite / sunWhite.y), to = kBradford * d65;
  const glm::dvec3 cone = kBradford * xyz;
  return glm::inverse(kBradford) * (cone * (to / from));
}

glm::dvec2 chromaticity(const glm::dvec3& xyz) {
  const double sum = xyz.x + xyz.y + xyz.z;
  return {xyz.x / sum, xyz.y / sum};
}

double correlatedColourTemperature(const glm::dvec2& xy) {
  const double n = (xy.x - 0.3320) / (xy.y - 0.1858);
  return ((-449.0 * n + 3525.0) * n - 6823.3) * n + 5520.33;
}

}  // namespace aal::test
