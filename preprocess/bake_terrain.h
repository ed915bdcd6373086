// What the bakers need of a heightfield, precomputed once: metric texel
// positions in the world frame and the surface slope (for the tangent-plane
// clamp of DESIGN §3).
#pragma once

#include <vector>

#include "heightfield.h"

namespace aal {

struct BakeTerrain {
  const Heightfield* field = nullptr;
  int width = 0, height = 0;
  // World-frame position of texel (col, row): x = (col - cx) * rowCellX[row]
  // (east), y = rowY[row] (north), origin at the DEM centre.
  std::vector<double> rowCellX, rowInvCellX;
  std::vector<double> rowY;
  double centreCol = 0;
  double cellY = 1;
  // Height gradient per texel in metres per metre, interleaved (one cache
  // line serves both): [2i] = dz/dx (east), [2i + 1] = dz/dy (north).
  std::vector<float> slopes;
  double maxHeight = 0;  // tallest texel, metres

  float slopeEast(size_t texel) const { return slopes[2 * texel]; }
  float slopeNorth(size_t texel) const { return slopes[2 * texel + 1]; }
  double x(int col, int row) const { return (col - centreCol) * rowCellX[row]; }
  double y(int row) const { return rowY[row]; }
};

// zScale and cell sizes are taken as already applied to the heightfield.
BakeTerrain prepareBakeTerrain(const Heightfield& field);

}  // namespace aal
