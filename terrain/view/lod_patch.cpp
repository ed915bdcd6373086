#include "aperture/terrain/view/lod_patch.h"

#include <algorithm>
#include <cmath>

#include <glm/common.hpp>

namespace aal {

std::vector<uint32_t> makeLodPatchIndices() {
  constexpr uint32_t n = kLodPatchQuads, half = n / 2, stride = n + 1;
  std::vector<uint32_t> indices;
  indices.reserve(kLodPatchIndices);
  for (uint32_t quadrant = 0; quadrant < 4; ++quadrant) {
    const uint32_t row0 = (quadrant / 2) * half, col0 = (quadrant % 2) * half;
    for (uint32_t r = row0; r < row0 + half; ++r) {
      for (uint32_t c = col0; c < col0 + half; ++c) {
        // Row r is north of row r + 1; seen from above (x east, y north) the
        // order north-west, south-west, south-east is counter-clockwise.
        const uint32_t nw = r * stride + c, ne = nw + 1, sw = nw + stride, se = sw + 1;
        indices.insert(indices.end(), {nw, sw, se, nw, se, ne});
      }
    }
  }
  return indices;
}

float lodMorphFactor(float distanceM, glm::vec2 morphRangeM) {
  const float k = (distanceM - morphRangeM.x) / (morphRangeM.y - morphRangeM.x);
  return std::clamp(k, 0.0f, 1.0f);
}

glm::vec2 lodMorphGridPoint(glm::vec2 gridPoint, float morphK) {
  // fract(g / 2) * 2 is 1 for odd and 0 for even integers, exactly.
  const auto odd = [](float g) { return (g * 0.5f - std::floor(g * 0.5f)) * 2.0f; };
  return {gridPoint.x - odd(gridPoint.x) * morphK, gridPoint.y - odd(gridPoint.y) * morphK};
}

glm::vec2 lodPatchTexel(const LodPatch& patch, glm::vec2 gridPoint, glm::vec2 demSizeTexels) {
  const glm::vec2 texel = glm::vec2(patch.node) + gridPoint * patch.node.z;
  return glm::min(texel, demSizeTexels - 1.0f);
}

}  // namespace aal
