#include "bake_terrain.h"

#include <algorithm>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "huge_pages.h"

namespace aal {

BakeTerrain prepareBakeTerrain(const Heightfield& field) {
  return prepareBakeTerrain(field, TexelWindow{0, 0, field.width, field.height});
}

BakeTerrain prepareBakeTerrain(const Heightfield& field, const TexelWindow& window) {
  if (window.width < 1 || window.height < 1 || window.col < 0 || window.row < 0 ||
      window.col + window.width > field.width || window.row + window.height > field.height) {
    throw std::invalid_argument("bake window outside the heightfield");
  }
  BakeTerrain t;
  t.field = &field;
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
  }

  // Central differences inside, one-sided at the edges of the field.
  t.window = window;
  assignOnHugePages(t.slopes, 2 * window.texelCount(), 0.0f);
  const int w = field.width, h = field.height;
  tbb::parallel_for(window.row, window.row + window.height, [&](int row) {
    const int north = row > 0 ? row - 1 : row, south = row + 1 < h ? row + 1 : row;
    const double dyNorth = (south - north) * field.cellSizeYM;
    for (int col = window.col; col < window.col + window.width; ++col) {
      const int west = col > 0 ? col - 1 : col, east = col + 1 < w ? col + 1 : col;
      const double dx = (east - west) * t.rowCellX[row];
      const size_t i = t.windowIndex(col, row);
      t.slopes[2 * i] =
          dx > 0 ? static_cast<float>((field.at(east, row) - field.at(west, row)) / dx) : 0.0f;
      t.slopes[2 * i + 1] =
          dyNorth > 0 ? static_cast<float>((field.at(col, north) - field.at(col, south)) / dyNorth)
                      : 0.0f;
    }
  });
  if (window.covers(field)) t.maxHeight = *std::max_element(field.z.begin(), field.z.end());
  return t;
}

}  // namespace aal
