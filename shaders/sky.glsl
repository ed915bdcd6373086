// Preetham et al. 1999 clear sky in GLSL: twin of terrain/light/sky_model.h (see
// there for the model, units and the twilight rule). The coefficients are
// computed on the CPU by makePreethamSky; radiance is photometric RGB in kcd/m².
#ifndef AAL_SKY_GLSL
#define AAL_SKY_GLSL

#include "config.h"

// Same layout as aal::PreethamSky (seven vec4: 112 bytes in std140 and std430).
// Channels .x = Y (luminance), .y = x, .z = y (CIE chromaticity).
struct PreethamSky {
  vec4 perezA;        // Perez A; w: turbidity
  vec4 perezB;        // Perez B; w: x of the midday CCT floor
  vec4 perezC;        // Perez C; w: strength of that floor
  vec4 perezD;        // Perez D (per radian)
  vec4 perezE;        // Perez E
  // (Y_z fade / F_Y(0, theta_s) [kcd/m²], x_z / F_x(0, theta_s), y_z / F_y(0, theta_s), fade)
  vec4 zenith;
  vec4 sunDirection;  // xyz: model sun direction (z up); w: true sun elevation (rad)
};

// CIE xyY to linear Rec. 709 / sRGB, negatives clamped.
vec3 xyYToLinearSrgb(float x, float y, float luminanceY) {
  float safeY = max(y, 1e-4);
  vec3 xyz = vec3(x * luminanceY / safeY, luminanceY, (1.0 - x - y) * luminanceY / safeY);
  vec3 rgb = vec3(dot(vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW0), xyz),
                  dot(vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW1), xyz),
                  dot(vec3(AAL_XYZ_TO_LINEAR_SRGB_ROW2), xyz));
  return max(rgb, vec3(0.0));
}

// The chromaticity y raised to the CIE daylight locus where it lies below it:
// twin of daylightLocusLift in terrain/light/sky_model.h (why: docs/sun-and-sky.md).
float daylightLocusLift(float x, float y) {
  float locus = (float(AAL_DAYLIGHT_LOCUS_A) * x + float(AAL_DAYLIGHT_LOCUS_B)) * x +
                float(AAL_DAYLIGHT_LOCUS_C);
  return max(y, locus);
}

// The midday colour-temperature floor, then the lift: twin of
// daylightChromaticity in terrain/light/sky_model.h (why: docs/sun-and-sky.md).
vec2 daylightChromaticity(float x, float y, float maxX, float strength) {
  float floored = x - strength * max(x - maxX, 0.0);
  float locusShift = ((float(AAL_DAYLIGHT_LOCUS_A) * floored + float(AAL_DAYLIGHT_LOCUS_B)) * floored +
                      float(AAL_DAYLIGHT_LOCUS_C)) -
                     ((float(AAL_DAYLIGHT_LOCUS_A) * x + float(AAL_DAYLIGHT_LOCUS_B)) * x +
                      float(AAL_DAYLIGHT_LOCUS_C));
  return vec2(floored, daylightLocusLift(floored, y + locusShift));
}

// Sky radiance (kcd/m², linear sRGB) along viewDir (any non-zero vector, z up):
// the Perez function of Y, x, y scaled by the zenith values (paper eq. 3), the
// chromaticity no warmer than the midday floor and on or above the daylight locus.
vec3 skyRadiance(PreethamSky sky, vec3 viewDir) {
  vec3 v = normalize(viewDir);
  vec3 s = sky.sunDirection.xyz;
  float cosTheta = max(v.z, float(AAL_SKY_MIN_COS_THETA));
  float gamma = 2.0 * atan(length(v - s), length(v + s));  // accurate next to the sun
  float cosGamma = clamp(dot(v, s), -1.0, 1.0);
  vec3 f = (1.0 + sky.perezA.xyz * exp(sky.perezB.xyz / cosTheta)) *
           (1.0 + sky.perezC.xyz * exp(sky.perezD.xyz * gamma) +
            sky.perezE.xyz * (cosGamma * cosGamma));
  vec3 yxy = sky.zenith.xyz * f;  // (Y, x, y)
  vec2 xy = daylightChromaticity(yxy.y, yxy.z, sky.perezB.w, sky.perezC.w);
  return xyYToLinearSrgb(xy.x, xy.y, yxy.x);
}

#endif
