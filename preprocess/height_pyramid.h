// A downsampled pyramid of a whole DEM for the far-field horizons of a tiled
// bake (docs/baking.md, "Far field"): level k holds, per block of 2^k x 2^k
// texels (smaller at the right and bottom edges), the maximum height, never
// below any texel it covers. Built from the DEM's rows in one pass, so a DEM
// read in bands never needs to be in memory whole; held in memory, or in an
// unnamed file, so that a rank's memory does not grow with the DEM (only
// the rectangles a tile reads are resident: readBlocks).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "aperture/terrain/heightfield.h"

namespace aal {

class HeightPyramid {
 public:
  struct Level {
    int shift = 0;  // blocks of 2^shift x 2^shift texels
    int width = 0, height = 0;
    size_t offset = 0;  // its first float in the storage
  };

  // An empty pyramid of a width x height DEM whose finest level has blocks
  // of 2^baseShift texels; the coarsest is one block. With a `fileFolder`,
  // the levels are kept in a file there that has no name (it goes when the
  // pyramid or the process goes, however the process ends); else in memory.
  HeightPyramid(int width, int height, int baseShift, const std::string& fileFolder = {});
  ~HeightPyramid();
  HeightPyramid(HeightPyramid&& other) noexcept;
  HeightPyramid& operator=(HeightPyramid&& other) noexcept;
  HeightPyramid(const HeightPyramid&) = delete;
  HeightPyramid& operator=(const HeightPyramid&) = delete;

  // Hands over the next `count` rows (width floats each), top to bottom.
  // After the last row the coarser levels are built.
  void addRows(const float* rows, int count);
  bool complete() const { return filledBlockRows_ == levels_.front().height; }
  // Rows [firstRow, firstRow + count), in any order and from any thread:
  // firstRow must start a block row of the finest level (a multiple of
  // 2^baseShift) and count be whole block rows unless the rows end at the
  // DEM's last row. Fills those block rows of the finest level (in
  // parallel), the same floats as addRows; after the last block row the
  // coarser levels are built. How a pass over the DEM split over threads or
  // MPI ranks fills the pyramid (preprocess/mpi_tiled_bake.h). Not mixed
  // with addRows.
  void addBlockRows(int firstRow, const float* rows, int count);
  // Instead of their rows: block rows [firstBlockRow, firstBlockRow + count)
  // of the finest level as another pyramid of the same DEM holds them (count
  // x level width maxima, readBlocks of the base level). How the ranks of an
  // MPI bake take the block rows other ranks made.
  void setBaseBlockRows(int firstBlockRow, int count, const float* max);

  // Copies the maxima of blocks [bx, bx + w) x [by, by + h) of the level of
  // blocks of 2^shift (inside it) to `out`, row after row. Any thread.
  void readBlocks(int shift, int bx, int by, int w, int h, float* out) const;
  // A whole level's maxima, row after row.
  std::vector<float> levelMax(int shift) const;

  int width() const { return width_; }
  int height() const { return height_; }
  int baseShift() const { return levels_.front().shift; }
  int coarsestShift() const { return levels_.back().shift; }
  // The level of blocks of 2^shift, shift in [baseShift, coarsestShift].
  const Level& level(int shift) const { return levels_[static_cast<size_t>(shift - baseShift())]; }
  bool inFile() const { return fd_ >= 0; }
  // Bytes of all levels: in memory, or in the file.
  size_t bytes() const { return floats_ * sizeof(float); }

 private:
  void writeFloats(size_t offset, const float* values, size_t count);
  void readFloats(size_t offset, float* values, size_t count) const;
  // Counts block rows [first, first + count) as filled, once each.
  void markFilled(int first, int count);
  void buildCoarserLevels();

  int width_, height_;
  size_t floats_ = 0;
  int fd_ = -1;
  std::vector<float> memory_;  // without a file
  int rowsAdded_ = 0;          // by addRows
  int filledBlockRows_ = 0;
  std::vector<char> filled_;  // per block row of the finest level
  std::vector<Level> levels_;
  std::vector<float> rowMax_;  // addRows: the base level's block row being filled
};

// The pyramid of a whole field (all its rows resident), in memory.
HeightPyramid buildHeightPyramid(const Heightfield& field, int baseShift);

// The finest block shift a march that starts at `startM` needs when it
// wants blocks no larger than 1/resolution of their distance on a grid
// whose largest cell is `largestCellM`.
int pyramidBaseShift(double startM, double largestCellM, int resolution);

}  // namespace aal
