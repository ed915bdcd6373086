#include "aperture/preprocess/bake_terrain.h"

#include <stdexcept>

namespace aal {

BakeTerrain prepareBakeTerrain(HeightView heights) {
  return prepareBakeTerrain(heights, TexelWindow{0, 0, heights.dem->width, heights.dem->height});
}

BakeTerrain prepareBakeTerrain(HeightView heights, const TexelWindow& window) {
  const Heightfield& field = *heights.dem;
  if (window.width < 1 || window.height < 1 || window.col < 0 || window.row < 0 ||
      window.col + window.width > field.width || window.row + window.height > field.height) {
    throw std::invalid_argument("bake window outside the heightfield");
  }
  BakeTerrain t;
  t.heights = heights;
  t.width = field.width;
  t.height = field.height;
  t.centreCol = 0.5 * (field.width - 1);
  t.cellY = field.cellSizeYM;
  t.rowCellX.resize(field.height);
  t.rowInvCellX.resize(field.height);
  t.rowY.resize(field.height);
  for (int row = 0; row < field.height; ++row) {
    t.rowCellX[row] = field.cellSizeXAtRow(row);
    t.rowInvCellX[row] = 1.0 / t.rowCellX[row];
    t.rowY[row] = (0.5 * (field.height - 1) - row) * field.cellSizeYM;  // row 0 is north
    t.uniformCellX = t.uniformCellX && t.rowCellX[row] == t.rowCellX[0];
  }

  t.window = window;
  t.pitch = window.width;
  return t;
}

int sumsPitch(int width) {
  return width % 64 == 0 ? width + 4 : width;
}

}  // namespace aal
