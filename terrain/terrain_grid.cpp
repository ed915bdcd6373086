#include "terrain_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace aal {

TerrainGrid makeTerrainGrid(int demWidth, int demHeight, size_t triangleBudget) {
  if (demWidth < 2 || demHeight < 2) throw std::invalid_argument("a DEM needs at least 2x2 texels");
  if (triangleBudget < 2) throw std::invalid_argument("triangle budget must be at least 2");
  TerrainGrid grid;
  grid.columns = demWidth - 1;
  grid.rows = demHeight - 1;
  const double full = 2.0 * grid.columns * grid.rows;
  if (full > static_cast<double>(triangleBudget)) {
    const double scale = std::sqrt(static_cast<double>(triangleBudget) / full);
    grid.columns = std::max(1, static_cast<int>(grid.columns * scale));
    grid.rows = std::max(1, static_cast<int>(grid.rows * scale));
  }
  const uint32_t stride = static_cast<uint32_t>(grid.columns + 1);
  grid.indices.reserve(static_cast<size_t>(grid.columns) * grid.rows * 6);
  for (uint32_t r = 0; r < static_cast<uint32_t>(grid.rows); ++r) {
    for (uint32_t c = 0; c < static_cast<uint32_t>(grid.columns); ++c) {
      // Row r is north of row r + 1; seen from above (x east, y north) the
      // order north-west, south-west, south-east is counter-clockwise.
      const uint32_t nw = r * stride + c, ne = nw + 1, sw = nw + stride, se = sw + 1;
      grid.indices.insert(grid.indices.end(), {nw, sw, se, nw, se, ne});
    }
  }
  return grid;
}

}  // namespace aal
