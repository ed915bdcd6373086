#include "aperture/terrain/light/tone_map.h"

#include <algorithm>
#include <cmath>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

constexpr float kA = float(AAL_FILMIC_A), kB = float(AAL_FILMIC_B), kC = float(AAL_FILMIC_C),
                kD = float(AAL_FILMIC_D), kE = float(AAL_FILMIC_E), kF = float(AAL_FILMIC_F),
                kW = float(AAL_FILMIC_W);

// Hable's curve before normalisation, (x (A x + C B) + D E) / (x (A x + B) + D F) - E / F,
// over one denominator: the D E F terms cancel, so h(0) = 0 exactly and no
// constant is subtracted. Same operation order as tone_map.glsl.
float hable(float x) {
  return x * (kF * (kA * x + kC * kB) - kE * (kA * x + kB)) / (kF * (x * (kA * x + kB) + kD * kF));
}

}  // namespace

float filmicCurve(float x) {
  return hable(std::clamp(x, 0.0f, kW)) / hable(kW);
}

float inverseFilmicCurve(float y) {
  // h(x) + E/F = t is a ratio of quadratics:
  //   A (1 - t) x^2 + B (C - t) x + D (E - t F) = 0,
  // whose non-negative root is taken in the form without cancellation.
  const double yy = std::clamp(double(y), 0.0, 1.0 - 1e-6);
  const double t = yy * double(hable(kW)) + double(kE) / double(kF);
  const double a = double(kA) * (1.0 - t);
  const double b = double(kB) * (double(kC) - t);
  const double c = double(kD) * (double(kE) - t * double(kF));
  const double root = std::sqrt(std::max(0.0, b * b - 4.0 * a * c));
  const double x = b >= 0.0 ? -2.0 * c / (b + root) : (-b + root) / (2.0 * a);
  return static_cast<float>(std::max(0.0, x));
}

float linearToSrgb(float linear) {
  const float c = std::clamp(linear, 0.0f, 1.0f);
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

glm::vec3 toneMap(const glm::vec3& linearHdr, float exposure) {
  glm::vec3 out;
  for (int i = 0; i < 3; ++i) {
    const float mapped = std::clamp(filmicCurve(linearHdr[i] * exposure), 0.0f, 1.0f);
    out[i] = linearToSrgb(mapped);
  }
  return out;
}

float exposureFromEv100(float ev100) {
  return 1000.0f / (1.2f * std::exp2(ev100));
}

float exposureForMiddleGrey(float sceneLuminance) {
  return inverseFilmicCurve(kMiddleGrey) / std::max(sceneLuminance, 1e-6f);
}

float flatTerrainLuminance(const glm::vec3& sunIrradiance, double sunElevationDeg,
                           const glm::vec3& skyRadiance, float albedo) {
  const double sinElevation = std::max(0.0, std::sin(sunElevationDeg * kPi / 180.0));
  const double irradiance =
      double(luminance(sunIrradiance)) * sinElevation + kPi * double(luminance(skyRadiance));
  return static_cast<float>(albedo / kPi * irradiance);
}

float autoExposure(const glm::vec3& sunIrradiance, double sunElevationDeg,
                   const glm::vec3& skyRadiance, float albedo) {
  return exposureForMiddleGrey(
      flatTerrainLuminance(sunIrradiance, sunElevationDeg, skyRadiance, albedo));
}

}  // namespace aal
