#include "aperture/terrain/light/shading.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/cap_table.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/units.h"

namespace aal {

const std::map<std::string, ShadingMode>& shadingModeNames() {
  static const std::map<std::string, ShadingMode> names = {
      {"approx", ShadingMode::Approx},
      {"exact", ShadingMode::Exact},
      {"baseline-lambert", ShadingMode::BaselineLambert},
      {"baseline-ao", ShadingMode::BaselineAo},
      {"debug-visible", ShadingMode::DebugVisible},
      {"debug-bent-normal", ShadingMode::DebugBentNormal},
      {"debug-sun", ShadingMode::DebugSunFraction},
      {"debug-sky", ShadingMode::DebugSkyFill},
      {"debug-obscurance", ShadingMode::DebugObscurance},
      {"debug-transfer", ShadingMode::DebugTransfer},
  };
  return names;
}

float horizonSunFraction(float sunElevationRad, float horizonRad, float sunRadiusRad) {
  if (!(sunRadiusRad > 0.0f)) return sunElevationRad > horizonRad ? 1.0f : 0.0f;
  const float x = std::clamp((sunElevationRad - horizonRad) / sunRadiusRad, -1.0f, 1.0f);
  return 1.0f - (std::acos(x) - x * std::sqrt(1.0f - x * x)) / kPiFloat;
}

float sunEdgeFootprintDistance(float apertureRad, float sunRadiusRad, float dRad, float spreadRad) {
  if (!(spreadRad > 0) || !(apertureRad > sunRadiusRad) || !(sunRadiusRad > 0)) return dRad;
  const float widened =
      std::min(std::sqrt(sunRadiusRad * sunRadiusRad + 5.0f * spreadRad * spreadRad),
               sunRadiusRad + float(AAL_SUN_EDGE_MAX_WIDENING_RAD));
  return apertureRad + (dRad - apertureRad) * (sunRadiusRad / widened);
}

float horizonMomentSunFraction(float sunElevationRad, float horizonMeanRad,
                               float horizonVarianceRad2, float sunRadiusRad) {
  const float spread = std::max(0.0f, horizonVarianceRad2);
  return horizonSunFraction(sunElevationRad, horizonMeanRad,
                            std::sqrt(sunRadiusRad * sunRadiusRad + 4.0f * spread));
}

ShadingTerms shadingTerms(const ShadingInputs& in, ShadingMode mode,
                          const CapIntersectionTable* exactTable) {
  ShadingTerms t;
  const glm::vec3 diffuse = in.albedo / kPiFloat;
  const float nDotL = std::max(0.0f, glm::dot(in.normal, in.sunDirection));
  const float visible = 1.0f - std::cos(in.apertureRad);  // Omega / 2 pi
  if (mode == ShadingMode::BaselineLambert || mode == ShadingMode::BaselineAo) {
    t.sunFraction = 1.0f;
    t.direct = diffuse * in.sunIrradiance * nDotL;
    // Constant ambient: the irradiance of the full sky dome, pi L_sky.
    t.skyIrradiance =
        kPiFloat * in.skyRadiance * (mode == ShadingMode::BaselineAo ? visible : 1.0f);
    t.ambient = diffuse * t.skyIrradiance;
    return t;
  }
  const float sunArea = static_cast<float>(capArea(in.sunRadiusRad));
  float sunSeen;  // the solid angle of the sun's disk in view, left out of the sky fill
  if (mode == ShadingMode::Horizon) {
    // The sun against the horizon in its azimuth; elevation as atan2 (asin
    // loses precision near the zenith, GPU versions more so). Its visible
    // part is the horizon's too, so the sky fill needs no cap intersection
    // (docs/rendering.md, "The horizon mode").
    const float elevation =
        std::atan2(in.sunDirection.z, glm::length(glm::vec2(in.sunDirection.x, in.sunDirection.y)));
    t.sunFraction = horizonMomentSunFraction(elevation, in.sunHorizonRad, in.sunHorizonVarianceRad2,
                                             in.sunRadiusRad);
    t.direct = diffuse * in.sunIrradiance * t.sunFraction * nDotL;
    sunSeen = t.sunFraction * sunArea;
  } else {
    // Sun: the fraction of its disk seen through the aperture, with the
    // Lambert term at the centroid of the visible part (caps.h).
    // Angle between the cap centres as atan2(|B x L|, B.L): acos loses
    // precision at the sun's scale (and GPU acos approximations more so).
    const float d = std::atan2(glm::length(glm::cross(in.bentNormal, in.sunDirection)),
                               glm::dot(in.bentNormal, in.sunDirection));
    const float dCap =
        sunEdgeFootprintDistance(in.apertureRad, in.sunRadiusRad, d, in.sunEdgeSpreadRad);
    if (mode != ShadingMode::Exact) {
      sunSeen = capIntersectionApprox(in.apertureRad, in.sunRadiusRad, dCap);
    } else if (exactTable) {
      sunSeen = capIntersectionFromTable(*exactTable, in.apertureRad, dCap);
    } else {
      sunSeen = static_cast<float>(capIntersectionExact(in.apertureRad, in.sunRadiusRad, dCap));
    }
    t.sunFraction = sunArea > 0 ? std::clamp(sunSeen / sunArea, 0.0f, 1.0f) : 0.0f;
    const glm::vec3 centroid =
        visibleLightCentroid(in.bentNormal, in.sunDirection, d, in.sunRadiusRad, t.sunFraction);
    t.direct =
        diffuse * in.sunIrradiance * t.sunFraction * std::max(0.0f, glm::dot(in.normal, centroid));
  }
  // Sky: a uniform cap of radius r_a centred beta from N gives pi sin^2(r_a)
  // cos(beta); the sun's share of the aperture is left out.
  const float apertureArea = static_cast<float>(capArea(in.apertureRad));
  const float skyShare = apertureArea > 0 ? 1.0f - std::min(1.0f, sunSeen / apertureArea) : 0.0f;
  const float sinR = std::sin(in.apertureRad);
  t.skyIrradiance = in.skyRadiance * kPiFloat * sinR * sinR *
                    std::max(0.0f, glm::dot(in.normal, in.bentNormal)) * skyShare;
  t.ambient = diffuse * t.skyIrradiance * in.transfer;
  return t;
}

glm::vec3 shade(const ShadingInputs& in, ShadingMode mode, const CapIntersectionTable* exactTable) {
  switch (mode) {
    case ShadingMode::DebugVisible: return glm::vec3(1.0f - std::cos(in.apertureRad));
    case ShadingMode::DebugBentNormal: return in.bentNormal * 0.5f + 0.5f;
    case ShadingMode::DebugSunFraction:
      return glm::vec3(shadingTerms(in, ShadingMode::Approx).sunFraction);
    case ShadingMode::DebugSkyFill: {
      const float full =
          kPiFloat * std::max({in.skyRadiance.r, in.skyRadiance.g, in.skyRadiance.b});
      const glm::vec3 e = shadingTerms(in, ShadingMode::Approx).skyIrradiance;
      return glm::vec3(full > 0 ? std::max({e.r, e.g, e.b}) / full : 0.0f);
    }
    case ShadingMode::DebugObscurance:
    case ShadingMode::DebugTransfer: return in.transfer;
    default: {
      const ShadingTerms t = shadingTerms(in, mode, exactTable);
      return t.direct + t.ambient;
    }
  }
}

}  // namespace aal
