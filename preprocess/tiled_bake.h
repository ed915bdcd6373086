// Tiled bake: the aperture map of a DEM too large for the in-memory bake,
// baked tile by tile into a folder (aperture_map.h's tiled map), resumable.
// Each tile is baked with the whole DEM's geometry and only the terrain
// within --max-distance of it (bakeApertureWindow), so the tiles equal the
// in-memory bake bit for bit. docs/baking.md.
#pragma once

#include <string>

#include "bake.h"

namespace aal {

// Above this many texels (16384 x 16384) a DEM is baked tiled: at the
// in-memory bake's ~20 bytes per texel the next size up, 32768 x 32768,
// would need ~22 GB, with the EXR writer's buffers and the system more than
// a 24 GiB machine has.
constexpr size_t kInMemoryBakeTexelLimit = size_t(16384) * 16384;
constexpr int kDefaultTileSize = 4096;
constexpr int kMinTileSize = 16, kMaxTileSize = 16384;

struct TiledBakeOptions {
  int tileSize = kDefaultTileSize;
  bool halfFloat = true;  // as writeApertureMap
  MapCompression compression = kDefaultMapCompression;
  std::string sourceName;  // aal:source (the DEM's file name)
};

struct TiledBakeSummary {
  int tiles = 0;
  int baked = 0;    // baked by this run
  int resumed = 0;  // found finished in the folder and kept
};

// Throws std::invalid_argument for options a tiled bake cannot take: a tile
// size outside [kMinTileSize, kMaxTileSize], no max distance, the ray
// method, the sky-view factor (bakeApertures' range checks apply too).
void checkTiledBakeOptions(const BakeOptions& bake, const TiledBakeOptions& tiled);

// Bakes `field` into `folder` (created if missing; its parent must exist):
// one EXR per tile, written as it finishes, then index.txt. Tiles already
// in the folder from an interrupted run of the same bake are kept
// (checked: readable, same DEM checksum, options and place); a tile or
// index of another DEM or other options is an InputError (nothing is
// overwritten). bake.progress sees the fraction over all tiles; bake.cancel
// stops between azimuths (BakeCancelled), keeping the finished tiles.
// Memory: the DEM (held by the caller) plus ~16 bytes per texel of one tile.
TiledBakeSummary bakeTiled(const Heightfield& field, const BakeOptions& bake,
                           const TiledBakeOptions& tiled, const std::string& folder);

class DemSource;

// The same bake, bit for bit, with the DEM read from `source` one band of
// rows at a time: a tile row plus the rows its sweeps read above and below
// it (bandHaloRows), every column. Memory: one band (4 bytes per texel of
// about three tile rows) plus one tile, whatever the DEM's height; the DEM
// is read once more for its checksum. `geometry` is demGeometry of the
// source. The DEM must have no voids (filling them needs all of it):
// InputError naming gdal_fillnodata.py otherwise, before any tile.
TiledBakeSummary bakeTiledInBands(const DemSource& source, const Heightfield& geometry,
                                  const BakeOptions& bake, const TiledBakeOptions& tiled,
                                  const std::string& folder);

// Rows above and below a tile row that its tiles' sweeps read: the tile
// size plus the max distance's steps (+ 3).
int bandHaloRows(const Heightfield& geometry, const BakeOptions& bake, int tileSize);

}  // namespace aal
