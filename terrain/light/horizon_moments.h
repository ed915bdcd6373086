// The horizons of a footprint as moments (docs/rendering.md, "Prefiltering
// the horizons: moments"): each mip level keeps, per stored direction, the
// mean of the horizon elevation and the mean of its square over the DEM
// texels it covers. Both are linear in the texels, so a trilinear fetch and
// the mean of the footprint's probes give the footprint's moments exactly,
// as the depth moments of Donnelly and Lauritzen, "Variance Shadow Maps"
// (I3D 2006). The GLSL twins are in shaders/slopes.glsl (the levels) and
// shaders/horizon_moments.glsl (the pair at the sun); the sun's visible
// fraction from the moments is horizonMomentSunFraction (shading.h).
#pragma once

#include <array>

namespace aal {

struct HorizonMoments {
  float mean = 0;    // E[h] (rad)
  float second = 0;  // E[h^2] (rad^2)
};

// One DEM texel's horizon.
HorizonMoments horizonMomentsOf(float horizonRad);

// A coarser level's texel from the 2 x 2 below: the mean of each moment.
HorizonMoments horizonMomentsMip(const HorizonMoments& a, const HorizonMoments& b,
                                 const HorizonMoments& c, const HorizonMoments& d);

// The horizon in the sun's azimuth over a footprint, from the moments of the
// two stored directions beside it and the frame's weights
// (horizonPairWeights, terrain/io/horizon_map.h): the mean is the weighted
// mean, as the per-texel interpolation of the two horizons gives; the
// variance the weighted variances of the two directions. Not the variance
// of the weighted second moments, which would add w0 w1 (m0 - m1)^2: the
// spread between the two directions, which the texels' interpolated horizon
// does not have (it blurred the shadows of a sun between two directions).
struct HorizonSpread {
  float mean = 0;      // rad
  float variance = 0;  // rad^2, >= 0
};
HorizonSpread horizonPairSpread(const HorizonMoments& first, const HorizonMoments& second,
                                std::array<float, 2> weights);

}  // namespace aal
