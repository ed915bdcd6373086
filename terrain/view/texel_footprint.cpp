#include "aperture/terrain/view/texel_footprint.h"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace aal {

FootprintProbes footprintProbes(glm::vec2 dx, glm::vec2 dy, int maxProbes) {
  const float lengthX = glm::dot(dx, dx), lengthY = glm::dot(dy, dy);
  const glm::vec2 major = lengthX >= lengthY ? dx : dy;
  const float majorTexels = std::sqrt(std::max(lengthX, lengthY));
  FootprintProbes p;
  if (!(majorTexels > 0.0f) || !std::isfinite(majorTexels)) return p;
  const float width = std::abs(dx.x * dy.y - dx.y * dy.x) / majorTexels;
  // Clamped while still a float: the ratio is infinite for a footprint with
  // no width. The tolerance keeps a square footprint, whose ratio rounds to
  // a little above 1, at one probe.
  const float ratio = majorTexels / std::max(width, 1e-30f);
  p.count = int(std::clamp(std::ceil(ratio - kFootprintRatioTolerance), 1.0f,
                           float(std::clamp(maxProbes, 1, kMaxFootprintProbes))));
  const float count = float(p.count);
  p.lod = std::max(0.0f, std::log2(std::max(width, majorTexels / count)));
  // The outermost probe's reach beyond the fragment's tile core: its offset
  // plus 1.5 texels of the coarser level it blends (terrain_textures.glsl).
  const float coarser =
      std::exp2(std::min(std::floor(p.lod) + 1.0f, float(AAL_TERRAIN_MIP_LEVELS - 1)));
  const float reach = float(AAL_TERRAIN_TILE_BORDER) - 1.5f * coarser;
  const float offset = 0.5f * (count - 1.0f) * majorTexels / count;
  p.step = major / count;
  if (offset > reach) p.step *= reach / offset;
  return p;
}

}  // namespace aal
