#include "aperture/terrain/light/horizon_moments.h"

#include <algorithm>

namespace aal {

HorizonMoments horizonMomentsOf(float horizonRad) {
  return {horizonRad, horizonRad * horizonRad};
}

HorizonMoments horizonMomentsMip(const HorizonMoments& a, const HorizonMoments& b,
                                 const HorizonMoments& c, const HorizonMoments& d) {
  return {((a.mean + b.mean) + (c.mean + d.mean)) * 0.25f,
          ((a.second + b.second) + (c.second + d.second)) * 0.25f};
}

HorizonSpread horizonPairSpread(const HorizonMoments& first, const HorizonMoments& second,
                                std::array<float, 2> weights) {
  // Each direction's variance clamped at 0: half-float moments of an even
  // footprint can come out a hair below the mean's square.
  const float firstVariance = std::max(0.0f, first.second - first.mean * first.mean);
  const float secondVariance = std::max(0.0f, second.second - second.mean * second.mean);
  return {weights[0] * first.mean + weights[1] * second.mean,
          weights[0] * firstVariance + weights[1] * secondVariance};
}

}  // namespace aal
