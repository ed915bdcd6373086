// Ambient aperture lighting of one surface point: twin of terrain/light/shading.h
// (see there for the contract and units). docs/design.md §5.
#ifndef AAL_SHADING_GLSL
#define AAL_SHADING_GLSL

#include "cap_table.glsl"
#include "caps.glsl"
#include "config.h"
#include "horizon_moments.glsl"

// The exact mode's cap intersection comes from a table made for the frame's
// sun radius (cap_table.glsl); the includer says where it is bound.
#ifndef AAL_CAP_TABLE_BINDING
#error "define AAL_CAP_TABLE_BINDING before including shading.glsl"
#endif
layout(set = 0, binding = AAL_CAP_TABLE_BINDING) uniform sampler2D capTable;

struct ShadingInputs {
  vec3 albedo;
  vec3 normal;
  vec3 bentNormal;
  float apertureRad;
  vec3 sunDirection;
  float sunRadiusRad;
  vec3 sunIrradiance;
  vec3 skyRadiance;
  vec3 transfer;
  float sunHorizonRad;  // horizon mode: the horizon's elevation in the sun's azimuth
  float sunHorizonVarianceRad2;  // and its variance over the footprint (rad^2)
  // approx, exact: the spread (standard deviation, rad) over the pixel's
  // footprint of the sun's distance from the aperture's edge; 0: a point.
  float sunEdgeSpreadRad;
};

struct ShadingTerms {
  vec3 direct;
  vec3 ambient;
  float sunFraction;
  vec3 skyIrradiance;
};

// Twin of sunEdgeFootprintDistance (terrain/light/shading.h): the distance
// at which the sun's cap meets the aperture's with the transition widened by
// the footprint's spread.
float sunEdgeFootprintDistance(float apertureRad, float sunRadiusRad, float dRad,
                               float spreadRad) {
  if (!(spreadRad > 0.0) || !(apertureRad > sunRadiusRad) || !(sunRadiusRad > 0.0)) return dRad;
  float widened = min(sqrt(sunRadiusRad * sunRadiusRad + 5.0 * spreadRad * spreadRad),
                      sunRadiusRad + float(AAL_SUN_EDGE_MAX_WIDENING_RAD));
  return apertureRad + (dRad - apertureRad) * (sunRadiusRad / widened);
}

ShadingTerms shadingTerms(ShadingInputs s, int mode) {
  const float pi = float(AAL_PI);
  ShadingTerms t;
  vec3 diffuse = s.albedo / pi;
  float nDotL = max(0.0, dot(s.normal, s.sunDirection));
  float visible = 1.0 - cos(s.apertureRad);
  if (mode == AAL_MODE_BASELINE_LAMBERT || mode == AAL_MODE_BASELINE_AO) {
    t.sunFraction = 1.0;
    t.direct = diffuse * s.sunIrradiance * nDotL;
    t.skyIrradiance = pi * s.skyRadiance * (mode == AAL_MODE_BASELINE_AO ? visible : 1.0);
    t.ambient = diffuse * t.skyIrradiance;
    return t;
  }
  float sunArea = capArea(s.sunRadiusRad);
  float sunSeen;  // the solid angle of the sun's disk in view, left out of the sky fill
  if (mode == AAL_MODE_HORIZON) {
    // Visible part from the horizon, no cap intersection (twin of shading.cpp).
    float elevation = atan(s.sunDirection.z, length(s.sunDirection.xy));
    t.sunFraction = horizonMomentSunFraction(elevation, s.sunHorizonRad,
                                             s.sunHorizonVarianceRad2, s.sunRadiusRad);
    t.direct = diffuse * s.sunIrradiance * t.sunFraction * nDotL;
    sunSeen = t.sunFraction * sunArea;
  } else {
    float d = capCentreDistance(s.bentNormal, s.sunDirection);
    float dCap = sunEdgeFootprintDistance(s.apertureRad, s.sunRadiusRad, d, s.sunEdgeSpreadRad);
    sunSeen = mode == AAL_MODE_EXACT
                  ? capIntersectionTable(capTable, s.apertureRad, s.sunRadiusRad, dCap)
                  : capIntersectionApprox(s.apertureRad, s.sunRadiusRad, dCap);
    t.sunFraction = sunArea > 0.0 ? clamp(sunSeen / sunArea, 0.0, 1.0) : 0.0;
    vec3 toCentroid =
        visibleLightCentroid(s.bentNormal, s.sunDirection, d, s.sunRadiusRad, t.sunFraction);
    t.direct = diffuse * s.sunIrradiance * t.sunFraction * max(0.0, dot(s.normal, toCentroid));
  }
  float apertureArea = capArea(s.apertureRad);
  float skyShare = apertureArea > 0.0 ? 1.0 - min(1.0, sunSeen / apertureArea) : 0.0;
  float sinR = sin(s.apertureRad);
  t.skyIrradiance = s.skyRadiance * pi * sinR * sinR * max(0.0, dot(s.normal, s.bentNormal)) *
                    skyShare;
  t.ambient = diffuse * t.skyIrradiance * s.transfer;
  return t;
}

vec3 shade(ShadingInputs s, int mode) {
  if (mode == AAL_MODE_DEBUG_VISIBLE) return vec3(1.0 - cos(s.apertureRad));
  if (mode == AAL_MODE_DEBUG_BENT_NORMAL) return s.bentNormal * 0.5 + 0.5;
  if (mode == AAL_MODE_DEBUG_SUN_FRACTION) return vec3(shadingTerms(s, AAL_MODE_APPROX).sunFraction);
  if (mode == AAL_MODE_DEBUG_SKY_FILL) {
    float full = float(AAL_PI) * max(s.skyRadiance.r, max(s.skyRadiance.g, s.skyRadiance.b));
    vec3 e = shadingTerms(s, AAL_MODE_APPROX).skyIrradiance;
    return vec3(full > 0.0 ? max(e.r, max(e.g, e.b)) / full : 0.0);
  }
  if (mode == AAL_MODE_DEBUG_OBSCURANCE || mode == AAL_MODE_DEBUG_TRANSFER) return s.transfer;
  ShadingTerms t = shadingTerms(s, mode);
  return t.direct + t.ambient;
}

#endif
