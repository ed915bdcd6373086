// The part of a DEM read in parts that a tile of a tiled bake is baked from:
// the tile and a halo around it in both directions, cut at the DEM's edges
// (docs/baking.md, "DEMs larger than memory"). Consecutive tiles of a tile
// row share most of their windows, so the window slides: what the next tile
// shares with the last is kept and only the new columns are read.
#pragma once

#include <cstdint>
#include <vector>

#include "aperture/terrain/height_window.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/texel_window.h"

namespace aal {

class DemSource;

// The texels tile `tile` of `geometry` is baked from: `halo` texels around
// it on every side (tileHalo, tiled_bake.h), cut at the DEM's edges.
TexelWindow tileReadWindow(const Heightfield& geometry, int halo, const TexelWindow& tile);

class TileWindowReader {
 public:
  // `geometry`: demGeometry of `source`; both must outlive the reader.
  TileWindowReader(const DemSource& source, const Heightfield& geometry, int halo);

  // The window of `tile` (tileReadWindow) as a HeightWindow of `geometry`,
  // valid until the next call. When the window held before has the same rows, the columns
  // both share are kept and only the others are read through the source;
  // otherwise the whole window is read. The previous window is freed once
  // the new one is complete (memory: two windows at most, and the new
  // columns). Voids: readDemWindow's InputError.
  const HeightWindow& windowFor(const TexelWindow& tile);

  // Samples read through the source by this reader.
  uint64_t texelsRead() const { return texelsRead_; }

 private:
  // Copies columns [col, col + columns) of every row of the new window
  // `want` into `z`, read through the source.
  void readColumns(const TexelWindow& want, int col, int columns, std::vector<float>& z);

  const DemSource& source_;
  const Heightfield& geometry_;
  const int halo_;
  HeightWindow window_;  // empty (texels.width 0): nothing held
  uint64_t texelsRead_ = 0;
};

}  // namespace aal
