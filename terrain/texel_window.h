// A rectangle of a DEM's texels, in the whole DEM's columns and rows: a tile
// of a tiled bake (preprocess/tiled_bake.h), or the texels whose heights a
// HeightWindow holds (terrain/height_window.h).
#pragma once

#include <cstddef>

#include "aperture/terrain/heightfield.h"

namespace aal {

struct TexelWindow {
  int col = 0, row = 0, width = 0, height = 0;

  size_t texelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  // Every texel of `field`.
  bool covers(const Heightfield& field) const {
    return col == 0 && row == 0 && width == field.width && height == field.height;
  }
  bool containsColumn(int x) const { return x >= col && x < col + width; }
  bool containsRow(int y) const { return y >= row && y < row + height; }
  // The first and last columns and rows of `inner` inside this one.
  bool contains(const TexelWindow& inner) const {
    return containsColumn(inner.col) && containsColumn(inner.col + inner.width - 1) &&
           containsRow(inner.row) && containsRow(inner.row + inner.height - 1);
  }
  // Where DEM texel (x, y), inside the rectangle, is in a row-major array of
  // the rectangle's texels.
  size_t index(int x, int y) const {
    return static_cast<size_t>(y - row) * static_cast<size_t>(width) + static_cast<size_t>(x - col);
  }
};

}  // namespace aal
