// A downsampled pyramid of a whole DEM for the far-field horizons of a tiled
// bake (docs/baking.md, "Far field"): level k holds, per block of 2^k x 2^k
// texels (smaller at the right and bottom edges), the maximum height, never
// below any texel it covers, and the mean. Built in one pass over the rows
// in order, so a DEM read in bands never needs to be in memory whole.
#pragma once

#include <cstddef>
#include <vector>

#include "aperture/terrain/heightfield.h"

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
  bool complete() const { return filledBlockRows_ == levels_.front().height; }
  // Rows [firstRow, firstRow + count), in any order: firstRow must start a
  // block row of the finest level (a multiple of 2^baseShift) and count be
  // whole block rows unless the rows end at the DEM's last row. Fills those
  // block rows of the finest level (in parallel), the same floats as
  // addRows; after the last block row the coarser levels are built. How a
  // pass over the DEM split over threads or MPI ranks fills the pyramid
  // (preprocess/mpi_tiled_bake.h). Not mixed with addRows.
  void addBlockRows(int firstRow, const float* rows, int count);
  // Instead of their rows: block rows [firstBlockRow, firstBlockRow + count)
  // of the finest level as another pyramid of the same DEM holds them (count
  // x level width maxima and means, from level(baseShift())). How the ranks
  // of an MPI bake take the block rows other ranks made.
  void setBaseBlockRows(int firstBlockRow, int count, const float* max, const float* mean);

  int width() const { return width_; }
  int height() const { return height_; }
  int baseShift() const { return levels_.front().shift; }
  int coarsestShift() const { return levels_.back().shift; }
  // The level of blocks of 2^shift, shift in [baseShift, coarsestShift].
  const Level& level(int shift) const { return levels_[static_cast<size_t>(shift - baseShift())]; }
  size_t bytes() const;

 private:
  void finishBlockRow(int blockRow);
  // Counts block rows [first, first + count) as filled, once each.
  void markFilled(int first, int count);
  void buildCoarserLevels();

  int width_, height_;
  int rowsAdded_ = 0;  // by addRows
  int filledBlockRows_ = 0;
  std::vector<char> filled_;  // per block row of the finest level
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
