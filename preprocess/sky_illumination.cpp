#include "aperture/preprocess/sky_illumination.h"

#include <tbb/parallel_for.h>

namespace aal {

void finishSkyIllumination(const BakeTerrain& terrain, std::vector<float>& sums, int azimuths,
                           SkyModel model) {
  const double pi = std::numbers::pi;
  const double horizontal = model == SkyModel::Uniform ? pi : 7 * pi / 3;
  const double scale = 2 * pi / azimuths / horizontal;
  tbb::parallel_for(size_t(0), sums.size(), [&](size_t i) {
    const double sx = terrain.slopeEast(i), sy = terrain.slopeNorth(i);
    sums[i] = static_cast<float>(scale * sums[i] / std::sqrt(1 + sx * sx + sy * sy));
  });
}

}  // namespace aal
