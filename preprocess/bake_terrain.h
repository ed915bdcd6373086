// What the bakers need of a heightfield, precomputed once: metric texel
// positions in the world frame and the surface slope (for the tangent-plane
// clamp of DESIGN §3).
#pragma once

#include <vector>

#include "heightfield.h"

namespace aal {

// A rectangle of texels of a heightfield: the part a tiled bake works on.
struct TexelWindow {
  int col = 0, row = 0, width = 0, height = 0;

  size_t texelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  bool covers(const Heightfield& field) const {
    return col == 0 && row == 0 && width == field.width && height == field.height;
  }
};

struct BakeTerrain {
  const Heightfield* field = nullptr;
  int width = 0, height = 0;
  // World-frame position of texel (col, row): x = (col - cx) * rowCellX[row]
  // (east), y = rowY[row] (north), origin at the DEM centre.
  std::vector<double> rowCellX, rowInvCellX;
  std::vector<double> rowY;
  double centreCol = 0;
  double cellY = 1;
  // The texels being baked: the whole field, or a tile of it. Positions,
  // heights and horizons are always the whole field's; slopes, the sweep's
  // visits and the bake's sums are indexed within the window (windowIndex).
  TexelWindow window;
  // Height gradient per window texel in metres per metre, interleaved (one
  // cache line serves both): [2i] = dz/dx (east), [2i + 1] = dz/dy (north).
  std::vector<float> slopes;
  // Tallest texel of the field, metres: for the ray baker, which bakes whole
  // fields only; the terrain of a smaller window leaves it unset (a tiled
  // bake would otherwise scan the whole DEM once per tile for nothing).
  double maxHeight = 0;

  float slopeEast(size_t texel) const { return slopes[2 * texel]; }
  float slopeNorth(size_t texel) const { return slopes[2 * texel + 1]; }
  double x(int col, int row) const { return (col - centreCol) * rowCellX[row]; }
  double y(int row) const { return rowY[row]; }
  size_t windowIndex(int col, int row) const {
    return static_cast<size_t>(row - window.row) * static_cast<size_t>(window.width) +
           static_cast<size_t>(col - window.col);
  }
};

// zScale and cell sizes are taken as already applied to the heightfield.
BakeTerrain prepareBakeTerrain(const Heightfield& field);
// The same for the texels of `window` only (inside the field): its slopes
// equal the whole field's there; maxHeight is set only when the window
// covers the whole field.
BakeTerrain prepareBakeTerrain(const Heightfield& field, const TexelWindow& window);

}  // namespace aal
