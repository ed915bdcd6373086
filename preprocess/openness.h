// Topographic openness (Yokoyama, Shirasawa & Pike, "Visualizing topography
// by openness: a new application of image processing to digital elevation
// models", 2002) from the bake's horizon sweeps. docs/baking.md, "Openness".
//
// Positive openness is the mean over the sweep's azimuths of the zenith
// angle of the horizon, 90° minus the largest signed elevation angle of the
// terrain ahead within the radius; negative openness is the mean nadir
// angle, 90° plus the smallest, which is the positive openness of the
// inverted DEM (-z). Both are 90° on a plane, in degrees.
//
// The positive one is summed from the horizons the bake's own sweep finds
// (SliceAccumulator); the negative one needs the lowest terrain, which the
// sweep's upper hull does not keep, so it is a second horizon sweep over -z.
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/sky_slice.h"

namespace aal {

// Adds the elevation angle (radians) of the horizon with tangent tanHorizon
// to a texel's running sum. An azimuth with no terrain ahead
// (kNoHorizonTangent: the texel is on an open DEM edge, looking out) has no
// angle: the sum becomes NaN, and so does the texel's openness, as in SAGA's
// line tracing, where a texel with such a direction is nodata.
inline void addHorizonAngle(float& sum, float tanHorizon) {
  sum += tanHorizon <= kNoHorizonTangent ? std::numeric_limits<float>::quiet_NaN()
                                         : fastAtan(tanHorizon);
}

// Turns sums of `azimuths` horizon angles into openness, in place: 90° minus
// their mean, in degrees.
void finishOpenness(std::vector<float>& sums, int azimuths);

// The negative openness of the texels of `window` (degrees, NaN where an
// azimuth has no terrain ahead): the positive openness of the inverted
// heights, by the sweeps of a bake with options `o` (the whole DEM's
// horizons, or those within o.maxDistanceM; not a far field, nor with Earth
// curvature: bakeApertureWindow and bakeApertures refuse both). `heights`
// holds the window and what its sweeps read (bake.h).
std::vector<float> negativeOpenness(HeightView heights, const TexelWindow& window,
                                    const BakeOptions& o);

}  // namespace aal
