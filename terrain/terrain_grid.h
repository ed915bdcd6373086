// The triangle grid that the renderer displaces with the height texture.
// Kept behind this small interface so that a quadtree LOD can replace it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace aal {

struct TerrainGrid {
  // Quads across and down; vertices are (columns + 1) x (rows + 1) and vertex
  // i sits at grid point (i % (columns + 1), i / (columns + 1)), spread
  // evenly over the DEM from its first to its last texel centre.
  int columns = 0, rows = 0;
  std::vector<uint32_t> indices;  // two counter-clockwise triangles per quad (seen from above)

  size_t triangleCount() const { return indices.size() / 3; }
};

// One quad per DEM cell, or a coarser regular grid when that would exceed
// `triangleBudget` (keeping the DEM's aspect ratio).
TerrainGrid makeTerrainGrid(int demWidth, int demHeight, size_t triangleBudget);

}  // namespace aal
