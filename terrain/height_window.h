// The heights of a rectangle of a DEM read in parts: a tile of a tiled bake
// and the halo around it (preprocess/tile_window_reader.h), or a band of
// rows (terrain/io/dem_loader.h's readDemRows), for DEMs larger than memory
// (docs/baking.md, "DEMs larger than memory"). Unlike a Heightfield, which
// is always the whole DEM, it holds only its rectangle's texels; it reads
// them in the whole DEM's columns and rows, so positions, lines and
// horizons are the whole DEM's.
#pragma once

#include <cstdint>
#include <vector>

#include "aperture/terrain/height_view.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/texel_window.h"

namespace aal {

struct HeightWindow {
  // The DEM the rectangle is of: its size, metric spacing, georeferencing
  // and nodata (demGeometry, whose z is empty). Not owned, and not copied
  // (a geographic grid's per-row spacing is 8 bytes per DEM row): it must
  // outlive the window.
  const Heightfield* dem = nullptr;
  TexelWindow texels;  // the rectangle, inside the DEM
  // texels.texelCount() heights in metres, row after row.
  std::vector<float> z;
  // Empty when the rectangle has no voids; else a flag per height, 1 = void.
  std::vector<uint8_t> voidMask;

  bool holdsColumn(int x) const { return texels.containsColumn(x); }
  bool holdsRow(int y) const { return texels.containsRow(y); }
  bool holds(int x, int y) const { return holdsColumn(x) && holdsRow(y); }
  // The rectangle is the whole DEM.
  bool holdsEveryTexel() const { return texels.covers(*dem); }
  // Where DEM texel (x, y), which must be held, is in z and voidMask.
  size_t index(int x, int y) const { return texels.index(x, y); }
  float at(int x, int y) const { return z[index(x, y)]; }
  bool isVoid(int x, int y) const { return !voidMask.empty() && voidMask[index(x, y)] != 0; }

  operator HeightView() const& {  // NOLINT(google-explicit-constructor): a view
    return HeightView(dem, texels, z, voidMask);
  }
  operator HeightView() const&& = delete;
};

// Rectangle `window` of a DEM held whole, `field`, copied out as a window of
// it (heights and void flags): what a DEM read in parts would hold there.
// `field` becomes the window's dem, so it must outlive the window.
inline HeightWindow windowOf(const Heightfield& field, const TexelWindow& window) {
  HeightWindow part;
  part.dem = &field;
  part.texels = window;
  part.z.reserve(window.texelCount());
  for (int row = window.row; row < window.row + window.height; ++row) {
    for (int col = window.col; col < window.col + window.width; ++col) {
      part.z.push_back(field.at(col, row));
    }
  }
  if (!field.voidMask.empty()) {
    part.voidMask.reserve(window.texelCount());
    for (int row = window.row; row < window.row + window.height; ++row) {
      for (int col = window.col; col < window.col + window.width; ++col) {
        part.voidMask.push_back(field.isVoid(col, row) ? 1 : 0);
      }
    }
  }
  return part;
}
HeightWindow windowOf(const Heightfield&& field, const TexelWindow& window) = delete;

}  // namespace aal
