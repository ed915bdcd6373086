#include "aperture/terrain/light/sky_model.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>
#include <glm/exponential.hpp>
#include <glm/geometric.hpp>

#include "aperture/terrain/units.h"

namespace aal {

namespace {

struct Perez {
  double a, b, c, d, e;
};

// Distribution coefficients, Preetham et al. 1999, App. A.2.
Perez perezLuminance(double t) {
  return {0.1787 * t - 1.4630, -0.3554 * t + 0.4275, -0.0227 * t + 5.3251, 0.1206 * t - 2.5771,
          -0.0670 * t + 0.3703};
}
Perez perezX(double t) {
  return {-0.0193 * t - 0.2592, -0.0665 * t + 0.0008, -0.0004 * t + 0.2125, -0.0641 * t - 0.8989,
          -0.0033 * t + 0.0452};
}
Perez perezY(double t) {
  return {-0.0167 * t - 0.2608, -0.0950 * t + 0.0092, -0.0079 * t + 0.2102, -0.0441 * t - 1.6537,
          -0.0109 * t + 0.0529};
}

// F(0, theta_s): the Perez function at the zenith, where gamma = theta_s.
double perezAtZenith(const Perez& p, double thetaSun) {
  const double cosSun = std::cos(thetaSun);
  return (1.0 + p.a * std::exp(p.b)) *
         (1.0 + p.c * std::exp(p.d * thetaSun) + p.e * cosSun * cosSun);
}

// Zenith luminance in kcd/m², App. A.2.
double zenithLuminance(double t, double thetaSun) {
  const double chi = (4.0 / 9.0 - t / 120.0) * (kPi - 2.0 * thetaSun);
  return (4.0453 * t - 4.9710) * std::tan(chi) - 0.2155 * t + 2.4192;
}

// Zenith chromaticity, App. A.2: [T^2 T 1] M [theta_s^3 theta_s^2 theta_s 1]^T.
double zenithChromaticity(const double (&m)[3][4], double t, double thetaSun) {
  const double th[4] = {thetaSun * thetaSun * thetaSun, thetaSun * thetaSun, thetaSun, 1.0};
  const double tt[3] = {t * t, t, 1.0};
  double sum = 0.0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 4; ++j) sum += tt[i] * m[i][j] * th[j];
  }
  return sum;
}

constexpr double kZenithX[3][4] = {{0.00166, -0.00375, 0.00209, 0.0},
                                   {-0.02903, 0.06377, -0.03202, 0.00394},
                                   {0.11693, -0.21196, 0.06052, 0.25886}};
constexpr double kZenithY[3][4] = {{0.00275, -0.00610, 0.00317, 0.0},
                                   {-0.04214, 0.08970, -0.04153, 0.00516},
                                   {0.15346, -0.26756, 0.06670, 0.26688}};

// CIE xyY to linear Rec. 709 / sRGB (IEC 61966-2-1), negatives clamped.
// Mirrors xyYToLinearSrgb in shaders/sky.glsl.
glm::vec3 xyYToLinearSrgb(float x, float y, float luminanceY) {
  const float safeY = std::max(y, 1e-4f);
  const glm::vec3 xyz(x * luminanceY / safeY, luminanceY, (1.0f - x - y) * luminanceY / safeY);
  const glm::vec3 rgb(glm::dot(glm::vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW0), xyz),
                      glm::dot(glm::vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW1), xyz),
                      glm::dot(glm::vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW2), xyz));
  return glm::max(rgb, glm::vec3(0.0f));
}

}  // namespace

float daylightLocusLift(float x, float y) {
  const float locus = (float(AAL_DAYLIGHT_LOCUS_A) * x + float(AAL_DAYLIGHT_LOCUS_B)) * x +
                      float(AAL_DAYLIGHT_LOCUS_C);
  return std::max(y, locus);
}

double daylightLocusX(double cctK) {
  const double t = std::clamp(cctK, 4000.0, 25000.0);
  const double u = 1e3 / t;  // 1000 / T: the coefficients below are per power of it
  return t <= 7000.0 ? ((-4.6070 * u + 2.9678) * u + 0.09911) * u + 0.244063
                     : ((-2.0064 * u + 1.9018) * u + 0.24748) * u + 0.237040;
}

double middayCctFloorStrength(double elevationDeg) {
  const double s = std::clamp(
      (elevationDeg - kMiddayFloorStartDeg) / (kMiddayFloorFullDeg - kMiddayFloorStartDeg), 0.0,
      1.0);
  return s * s * (3.0 - 2.0 * s);
}

glm::vec2 daylightChromaticity(float x, float y, float maxX, float strength) {
  const auto locus = [](float u) {
    return (float(AAL_DAYLIGHT_LOCUS_A) * u + float(AAL_DAYLIGHT_LOCUS_B)) * u +
           float(AAL_DAYLIGHT_LOCUS_C);
  };
  const float floored = x - strength * std::max(x - maxX, 0.0f);
  return {floored, daylightLocusLift(floored, y + (locus(floored) - locus(x)))};
}

namespace {

glm::vec4 pack(double y, double x, double yy, double w = 0.0) {
  return glm::vec4(static_cast<float>(y), static_cast<float>(x), static_cast<float>(yy),
                   static_cast<float>(w));
}

// Midpoint rule over cells of equal solid angle; returns (uniform mean,
// cosine-weighted mean times 2), both per steradian of the hemisphere.
void integrateHemisphere(const PreethamSky& sky, int azimuthSteps, int zenithSteps,
                         glm::dvec3& uniformMean, glm::dvec3& cosineMean) {
  const int na = std::max(1, azimuthSteps), nz = std::max(1, zenithSteps);
  glm::dvec3 sum(0.0), sumCos(0.0);
  for (int j = 0; j < nz; ++j) {
    const double z = (j + 0.5) / nz;
    const double r = std::sqrt(1.0 - z * z);
    for (int i = 0; i < na; ++i) {
      const double phi = 2.0 * kPi * (i + 0.5) / na;
      const glm::vec3 dir(static_cast<float>(r * std::cos(phi)),
                          static_cast<float>(r * std::sin(phi)), static_cast<float>(z));
      const glm::dvec3 l(skyRadiance(sky, dir));
      sum += l;
      sumCos += l * z;
    }
  }
  const double n = double(na) * double(nz);
  uniformMean = sum / n;
  cosineMean = 2.0 * sumCos / n;  // (1/pi) * (2 pi / n) * sum(L cos theta)
}

}  // namespace

double twilightFade(double elevationDeg) {
  if (elevationDeg >= 0.0) return 1.0;
  if (elevationDeg <= kCivilTwilightDeg) return 0.0;
  const double s = (elevationDeg - kCivilTwilightDeg) / -kCivilTwilightDeg;  // 0 at -6°, 1 at 0°
  return std::pow(10.0, 0.4 * elevationDeg) * s * s * (3.0 - 2.0 * s);
}

PreethamSky makePreethamSky(const glm::vec3& sunDir, double turbidity) {
  const double t = std::clamp(turbidity, kMinSkyTurbidity, kMaxSkyTurbidity);
  const double length = glm::length(glm::dvec3(sunDir));
  const glm::dvec3 sun = length > 0.0 ? glm::dvec3(sunDir) / length : glm::dvec3(0, 0, 1);
  const double elevationRad = std::asin(std::clamp(sun.z, -1.0, 1.0));

  // Below the horizon the model runs with the sun on the horizon, same azimuth.
  glm::dvec3 modelSun = sun;
  if (sun.z < 0.0) {
    const double horizontal = std::hypot(sun.x, sun.y);
    modelSun = horizontal > 1e-9 ? glm::dvec3(sun.x / horizontal, sun.y / horizontal, 0.0)
                                 : glm::dvec3(0.0, 1.0, 0.0);
  }
  const double thetaSun = std::acos(std::clamp(modelSun.z, -1.0, 1.0));

  const Perez pY = perezLuminance(t), px = perezX(t), py = perezY(t);
  const double fade = twilightFade(elevationRad * 180.0 / kPi);
  const double yz = std::max(0.0, zenithLuminance(t, thetaSun));
  const double xz = zenithChromaticity(kZenithX, t, thetaSun);
  const double yzChroma = zenithChromaticity(kZenithY, t, thetaSun);

  PreethamSky sky;
  sky.perezA = pack(pY.a, px.a, py.a, t);
  sky.perezB = pack(pY.b, px.b, py.b, daylightLocusX(kMiddaySkyMinCctK));
  sky.perezC = pack(pY.c, px.c, py.c, middayCctFloorStrength(elevationRad * 180.0 / kPi));
  sky.perezD = pack(pY.d, px.d, py.d);
  sky.perezE = pack(pY.e, px.e, py.e);
  sky.zenith = pack(yz * fade / perezAtZenith(pY, thetaSun), xz / perezAtZenith(px, thetaSun),
                    yzChroma / perezAtZenith(py, thetaSun), fade);
  sky.sunDirection = pack(modelSun.x, modelSun.y, modelSun.z, elevationRad);
  return sky;
}

glm::vec3 skyRadiance(const PreethamSky& sky, const glm::vec3& viewDir) {
  const glm::vec3 v = glm::normalize(viewDir);
  const glm::vec3 s(sky.sunDirection);
  const float cosTheta = std::max(v.z, float(AAL_SKY_MIN_COS_THETA));
  const float gamma = 2.0f * std::atan2(glm::length(v - s), glm::length(v + s));
  const float cosGamma = std::clamp(glm::dot(v, s), -1.0f, 1.0f);
  const glm::vec3 a(sky.perezA), b(sky.perezB), c(sky.perezC), d(sky.perezD), e(sky.perezE);
  const glm::vec3 f = (1.0f + a * glm::exp(b / cosTheta)) *
                      (1.0f + c * glm::exp(d * gamma) + e * (cosGamma * cosGamma));
  const glm::vec3 yxy = glm::vec3(sky.zenith) * f;  // (Y, x, y)
  const glm::vec2 xy = daylightChromaticity(yxy.y, yxy.z, sky.perezB.w, sky.perezC.w);
  return xyYToLinearSrgb(xy.x, xy.y, yxy.x);
}

glm::vec3 averageSkyRadiance(const PreethamSky& sky, int azimuthSteps, int zenithSteps) {
  glm::dvec3 uniformMean, cosineMean;
  integrateHemisphere(sky, azimuthSteps, zenithSteps, uniformMean, cosineMean);
  return glm::vec3(uniformMean);
}

glm::vec3 cosineWeightedSkyRadiance(const PreethamSky& sky, int azimuthSteps, int zenithSteps) {
  glm::dvec3 uniformMean, cosineMean;
  integrateHemisphere(sky, azimuthSteps, zenithSteps, uniformMean, cosineMean);
  return glm::vec3(cosineMean);
}

}  // namespace aal
