// The sun against the horizons of a footprint: twins of horizonSunFraction
// and horizonMomentSunFraction (terrain/light/shading.h) and of
// horizonPairSpread (terrain/light/horizon_moments.h), the mean and
// variance of the horizon in the sun's azimuth over a footprint, from the
// moments of the two stored directions beside it (means in the slopes' B
// and A, second moments in the horizon moment texture, both filtered over
// the footprint) and the frame's weights. The variance is the weighted
// variances of the two directions, not that of the weighted moments (which
// would add the spread between the directions).
#ifndef AAL_HORIZON_MOMENTS_GLSL
#define AAL_HORIZON_MOMENTS_GLSL

#include "config.h"

// Twin of horizonSunFraction (terrain/light/shading.h): the part of the sun's disk
// above a straight horizon.
float horizonSunFraction(float sunElevationRad, float horizonRad, float sunRadiusRad) {
  if (!(sunRadiusRad > 0.0)) return sunElevationRad > horizonRad ? 1.0 : 0.0;
  float x = clamp((sunElevationRad - horizonRad) / sunRadiusRad, -1.0, 1.0);
  return 1.0 - (acos(x) - x * sqrt(1.0 - x * x)) / float(AAL_PI);
}

// Twin of horizonMomentSunFraction (terrain/light/shading.h): the expected
// share of the disk above the horizons of a footprint of this mean and
// variance, as a disk whose radius adds their spread (variance r^2/4 + v).
float horizonMomentSunFraction(float sunElevationRad, float horizonMeanRad,
                               float horizonVarianceRad2, float sunRadiusRad) {
  float spread = max(0.0, horizonVarianceRad2);
  return horizonSunFraction(sunElevationRad, horizonMeanRad,
                            sqrt(sunRadiusRad * sunRadiusRad + 4.0 * spread));
}

// x: the mean (rad), y: the variance (rad^2).
vec2 horizonPairSpread(vec2 means, vec2 secondMoments, vec2 weights) {
  vec2 variances = max(secondMoments - means * means, vec2(0.0));
  return vec2(dot(means, weights), dot(variances, weights));
}

#endif
