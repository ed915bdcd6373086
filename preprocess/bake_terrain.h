// What the bakers need of a heightfield: metric texel positions in the world
// frame, precomputed once per row, and the surface slope (for the
// tangent-plane clamp of docs/design.md §3), computed where it is needed.
#pragma once

#include <vector>

#include "aperture/terrain/height_view.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/texel_window.h"

namespace aal {

struct BakeTerrain {
  // The heights the bake reads: the whole DEM's, or those of a window of it
  // that holds the texels being baked and what their sweeps read around
  // them (tileHalo, tiled_bake.h). heights.dem is the DEM.
  HeightView heights;
  int width = 0, height = 0;  // the DEM's
  // World-frame position of texel (col, row): x = (col - cx) * rowCellX[row]
  // (east), y = rowY[row] (north), origin at the DEM centre.
  std::vector<double> rowCellX, rowInvCellX;
  std::vector<double> rowY;
  bool uniformCellX = true;  // every row's rowCellX the same (not a geographic grid)
  double centreCol = 0;
  double cellY = 1;
  // The texels being baked: the whole field, or a tile of it. Positions,
  // heights and horizons are always the whole field's; the sweep's visits
  // and the bake's sums are indexed within the window (windowIndex).
  TexelWindow window;
  // The row pitch, in texels, of the arrays indexed by windowIndex: the
  // window's width (prepareBakeTerrain), or a few texels more for the
  // sweep's sums (sumsPitch).
  int pitch = 0;

  // Height gradient at field texel (col, row) in metres per metre, dz/dx
  // (east) and dz/dy (north): central differences inside, one-sided at the
  // field's edges, 0 across a field one texel wide. Single precision, in
  // exactly the operations of the block sweep, which computes the same
  // values from the heights its walk loads anyway (block_line_walker.cpp,
  // bake_avx2.cpp): no stored slopes, which cost 8 bytes per texel of
  // memory and of traffic per azimuth pair.
  float slopeEastAt(int col, int row) const {
    const int west = col > 0 ? col - 1 : col, east = col + 1 < width ? col + 1 : col;
    return (heights.at(east, row) - heights.at(west, row)) *
           (differenceScale(west, east) * static_cast<float>(rowInvCellX[row]));
  }
  float slopeNorthAt(int col, int row) const {
    const int north = row > 0 ? row - 1 : row, south = row + 1 < height ? row + 1 : row;
    return (heights.at(col, north) - heights.at(col, south)) *
           (differenceScale(north, south) * invCellYF());
  }
  // The same at window texel i (windowIndex).
  float slopeEast(size_t texel) const {
    return slopeEastAt(window.col + static_cast<int>(texel % size_t(pitch)),
                       window.row + static_cast<int>(texel / size_t(pitch)));
  }
  float slopeNorth(size_t texel) const {
    return slopeNorthAt(window.col + static_cast<int>(texel % size_t(pitch)),
                        window.row + static_cast<int>(texel / size_t(pitch)));
  }
  // The factor of a difference between neighbours lo and hi (lo <= hi, at
  // most two texels apart) that makes it one per texel.
  static float differenceScale(int lo, int hi) {
    return hi - lo == 2 ? 0.5f : (hi - lo == 1 ? 1.0f : 0.0f);
  }
  float invCellYF() const { return static_cast<float>(1.0 / cellY); }
  double x(int col, int row) const { return (col - centreCol) * rowCellX[row]; }
  double y(int row) const { return rowY[row]; }
  size_t windowIndex(int col, int row) const {
    return static_cast<size_t>(row - window.row) * static_cast<size_t>(pitch) +
           static_cast<size_t>(col - window.col);
  }
  // How many entries an array indexed by windowIndex holds.
  size_t pitchedTexelCount() const { return static_cast<size_t>(pitch) * window.height; }
};

// A row pitch for the sweep's sums of a window `width` texels wide: the
// width, or 4 texels more where the width is a multiple of 64. A group of
// lines walked across rows adds to one texel of each of some 40 rows per
// step; at such widths an array's rows lie a multiple of 256 bytes apart
// and fall into a few of the L1 cache's 64 sets (one at multiples of 1024
// texels), which hold 8 lines each. It is the GIS rasters' 4-byte sums
// that gained (2048² --svf 10 % faster); the aperture sums, prefetched
// ahead, did not change (docs/performance.md, "Power-of-two widths").
int sumsPitch(int width);

// zScale and cell sizes are taken as already applied to the heights. The
// terrain views `heights`, which must outlive it.
BakeTerrain prepareBakeTerrain(HeightView heights);
// The same for the texels of `window` only (inside the DEM; the heights
// must hold them and what their sweeps read: bakeApertureWindow checks).
BakeTerrain prepareBakeTerrain(HeightView heights, const TexelWindow& window);

}  // namespace aal
