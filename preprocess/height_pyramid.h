// A downsampled pyramid of a whole DEM for the far-field horizons of a tiled
// bake (docs/baking.md, "Far field"): level k holds, per block of 2^k x 2^k
// texels (smaller at the right and bottom edges), the maximum height, never
// below any texel it covers, and the mean. Built in one pass over the rows
// in order, so a DEM read in bands never needs to be in memory whole.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "heightfield.h"

namespace aal {

class HeightPyramid {
 public:
  struct Level {
    int shift = 0;  // blocks of 2^shift x 2^shift texels
    int width = 0, height = 0;
    std::vector<float> max, mean;

    float maxAt(int bx, int by) const { return max[static_cast<size_t>(by) * width + bx]; }
    float meanAt(int bx, int by) const { return mean[static_cast<size_t>(by) * width + bx]; }
  };

  // An empty pyramid of a width x height DEM whose finest level has blocks
  // of 2^baseShift texels; the coarsest is one block.
  HeightPyramid(int width, int height, int baseShift);

  // Hands over the next `count` rows (width floats each), top to bottom.
  // After the last row the coarser levels are built.
  void addRows(const float* rows, int count);
  bool complete() const { return rowsAdded_ == height_; }
  // Instead of the rows: `fill` writes the finest level's maxima and means
  // (`count` floats each, in place) as another pyramid of the same DEM holds
  // them (level(baseShift())), then the coarser levels are built, the same
  // bit for bit. How the ranks of an MPI bake take the pyramid that rank 0
  // built (preprocess/mpi_tiled_bake.h).
  void fillBaseLevel(const std::function<void(float* max, float* mean, size_t count)>& fill);

  int width() const { return width_; }
  int height() const { return height_; }
  int baseShift() const { return levels_.front().shift; }
  int coarsestShift() const { return levels_.back().shift; }
  // The level of blocks of 2^shift, shift in [baseShift, coarsestShift].
  const Level& level(int shift) const { return levels_[static_cast<size_t>(shift - baseShift())]; }
  size_t bytes() const;

 private:
  void finishBlockRow(int blockRow);
  void buildCoarserLevels();

  int width_, height_;
  int rowsAdded_ = 0;
  std::vector<Level> levels_;
  std::vector<double> rowSums_;  // the base level's block row being filled
};

// The pyramid of a whole field (all its rows resident).
HeightPyramid buildHeightPyramid(const Heightfield& field, int baseShift);

// The finest block shift a march that starts at `startM` needs when it
// wants blocks no larger than 1/resolution of their distance on a grid
// whose largest cell is `largestCellM`.
int pyramidBaseShift(double startM, double largestCellM, int resolution);

}  // namespace aal
