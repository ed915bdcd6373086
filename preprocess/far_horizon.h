// Far-field horizons of a tiled bake without a max distance (docs/baking.md,
// "Far field"): beyond the reach of the near sweep, which walks each tile's
// lines only from its window (tile + halo), the terrain comes from a
// downsampled pyramid of the whole DEM (height_pyramid.h). Each line of the
// window's sweep starts with the pyramid's block maxima beyond its first
// point, in blocks that grow with their distance, in its hull: the sweep
// then sees them from every texel of the line as it sees the near terrain.
#pragma once

#include <string>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/height_pyramid.h"

namespace aal {

struct FarFieldOptions {
  // The near sweep covers at least this distance (metres) ahead of every
  // texel; the far samples start there.
  double nearReachM = 0.0;
  // Blocks no larger than 1/resolution of their distance from the texels.
  int resolution = 16;
};

// The finest pyramid level the far field reads (HeightPyramid's base
// shift): blocks of at most nearReachM / resolution. largestCellM: the
// field's largest cell.
int farFieldBaseShift(const FarFieldOptions& options, double largestCellM);
// How far before the first texel it passes beside a far-field bake walks
// each line (the window sweeps' HorizonSweepOptions::windowReachM): the
// near reach and two blocks of the pyramid's finest level. The block under
// a line's first far sample, half a block beyond the line's start, reaches
// up to sqrt(2) blocks back from that sample, so without the two blocks it
// could hold terrain inside the near reach of the line's first texel,
// placed farther than it lies (its maximum at the sample's distance): a
// horizon there came out lower than the in-memory bake's
// (FarField.MaximaNeverSeeMoreSkyThanTheTerrainAllows).
double farFieldWalkReachM(const FarFieldOptions& options, double largestCellM);
// The bake's aal:method with this far field, e.g. "sweep+far-field(max,
// reach 3840 m, lines, blocks 1/16)": resuming a folder with other
// far-field options (or a folder of the lattice far field, "lattice 16") is
// refused as a bake with other options.
std::string farFieldMethod(const FarFieldOptions& options);

// How far beyond a line's start (m) FarLineMarch reads the level of
// blocks of 2^shift (below the coarsest) on a DEM whose largest cell is
// largestCellM: a sample d beyond it comes from that level while
// R + d < 2^(shift+1) x resolution cells. Not above 0: never read.
double farLevelReachM(const FarFieldOptions& options, double largestCellM, int shift);

struct FarField {
  const HeightPyramid* pyramid = nullptr;  // the whole DEM's
  FarFieldOptions options;
};

// The blocks of each pyramid level that the lines of one window's sweep
// read, copied out of the pyramid: a sample d beyond a line's start comes
// from a level of blocks no finer than (R + d) / resolution, so a level of
// blocks of b cells is read no farther than about 2 b resolution from the
// window. The finest levels are read only around the window and every
// level holds some 64 x 64 blocks beyond it: the resident part stays small
// however large the DEM (docs/baking.md, "Far field").
class FarFieldWindow {
 public:
  // For the sweep of terrain.window (a tile) from the heights terrain holds.
  FarFieldWindow(const FarField& far, const BakeTerrain& terrain);

  struct Level {
    int shift = 0;
    int x0 = 0, y0 = 0, width = 0, height = 0;  // blocks held
    std::vector<float> max;

    // The maximum of block (bx, by) of the level; a block outside those
    // held is a logic_error.
    float maxAt(int bx, int by) const {
      const unsigned x = static_cast<unsigned>(bx - x0), y = static_cast<unsigned>(by - y0);
      if (x >= static_cast<unsigned>(width) || y >= static_cast<unsigned>(height)) outside(bx, by);
      return max[static_cast<size_t>(y) * static_cast<size_t>(width) + x];
    }
    [[noreturn]] void outside(int bx, int by) const;
  };

  const FarFieldOptions& options() const { return options_; }
  int baseShift() const { return levels_.front().shift; }
  int coarsestShift() const { return levels_.back().shift; }
  // The level of blocks of 2^shift, shift in [baseShift, coarsestShift].
  const Level& level(int shift) const { return levels_[static_cast<size_t>(shift - baseShift())]; }
  size_t bytes() const;
  // The DEM's smallest and largest cell (m), north-south included.
  double smallestCellM() const { return smallestCell_; }
  double largestCellM() const { return largestCell_; }
  // How far before its first texel the window's sweep walks each line
  // (farFieldWalkReachM).
  double walkReachM() const { return farFieldWalkReachM(options_, largestCell_); }

 private:
  FarFieldOptions options_;
  double smallestCell_ = 0, largestCell_ = 0;
  std::vector<Level> levels_;
};

// The far samples of the lines of azimuth phi (radians from east,
// counter-clockwise) of a window's sweep, from the window's terrain. Where a
// line's walk starts every texel it visits lies at least the near reach R
// behind, so a sample d beyond the start is at least R + d from them: it is
// read from the level whose blocks are at most (R + d) / resolution, one
// level coarser at each doubling, every half block, to the DEM's edge.
class FarLineMarch {
 public:
  FarLineMarch(const FarFieldWindow& far, const BakeTerrain& terrain, double phi);

  // The samples beyond the point at field column colF, row rowF (texel
  // units, inside the DEM), nearest first: the distance beyond the point
  // along u (m) and the block's maximum (m). Clears `distance` and
  // `height` first.
  void march(double colF, double rowF, std::vector<float>& distance,
             std::vector<float>& height) const;

 private:
  const FarFieldWindow& far_;
  const BakeTerrain& terrain_;
  double ux_, uy_;
};

}  // namespace aal
