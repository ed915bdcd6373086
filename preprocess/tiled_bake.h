// Tiled bake: the aperture map of a DEM too large for the in-memory bake,
// baked tile by tile into a folder (aperture_map.h's tiled map), resumable.
// Each tile is baked with the whole DEM's geometry and only the terrain
// within --max-distance of it (bakeApertureWindow), so the tiles equal the
// in-memory bake bit for bit; without a max distance, with the terrain
// within a near reach of it plus far-field horizons from a pyramid of the
// whole DEM (far_horizon.h), close to the in-memory bake. docs/baking.md.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/far_horizon.h"
#include "aperture/preprocess/height_pyramid.h"
#include "aperture/terrain/io/geotiff_writer.h"

namespace aal {

// The file in a tile folder whose flock a bake holds while it runs. The bake
// removes it when it ends (TiledBakeLock); only a killed one leaves it.
constexpr const char* kTiledBakeLockName = ".aal-bake.lock";
// Written into the folder before any tile, in index.txt's format: whose
// bake the folder holds while it has no index.txt yet.
constexpr const char* kTiledBakeManifestName = "manifest.txt";

// Whether a tiled bake (aal-bake --tile-size, aal-bake-mpi) writes a file
// of this name into its folder: a tile (apertureTileName), an SVF tile
// (skyViewFactorTileName), the SVF mosaic, index.txt, the manifest or the
// lock. An input of such a name in the folder would be overwritten
// (tools/tool_paths.h checks for it before any work).
bool isTiledBakeFileName(const std::string& name);
// Those names in words, for messages.
constexpr const char* kTiledBakeFileNames =
    "tile_ROW_COL.exr, svf_ROW_COL.tif, sky_view_factor.vrt, index.txt, manifest.txt, "
    ".aal-bake.lock";

// Another process holds the folder's lock: a runtime condition (exit 1), not
// bad input; the same command succeeds once that bake has finished.
class TiledBakeBusy : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An exclusive, non-blocking flock on FOLDER/.aal-bake.lock, held while the
// object lives (the kernel drops it when the process dies). The folder must
// exist. Throws TiledBakeBusy, naming the folder, when another process (or
// another open of the file) holds it, std::runtime_error when the file
// cannot be opened. The file is removed when the lock is released: a bake
// refused, interrupted or finished leaves no lock file behind (a killed one
// does, and the next bake in the folder removes it).
class TiledBakeLock {
 public:
  explicit TiledBakeLock(const std::string& folder);
  ~TiledBakeLock();
  TiledBakeLock(const TiledBakeLock&) = delete;
  TiledBakeLock& operator=(const TiledBakeLock&) = delete;

 private:
  std::string path_;
  int fd_ = -1;
};

// Above this many texels (16384 x 16384) a DEM and its map are baked tiled: at the
// in-memory bake's ~20 bytes per texel the next size up, 32768 x 32768,
// would need ~22 GB, with the EXR writer's buffers and the system more than
// a 24 GiB machine has.
constexpr size_t kInMemoryBakeTexelLimit = size_t(16384) * 16384;
// GIS rasters alone (no aperture map: BakeOptions::apertureMap false) hold
// about 6 bytes per texel plus 4 per raster, so twice the side fits as
// well (32768 x 32768 with --svf: ~11 GB), when the memory check lets it.
constexpr size_t kInMemoryRasterBakeTexelLimit = size_t(32768) * 32768;
// What an in-memory bake holds at its peak per texel, with a margin over
// the 20.2 B measured at 16384^2 (docs/performance.md), before --svf,
// --visible (4 B each) and --horizons (1 B per direction) add theirs.
constexpr double kInMemoryBakeBytesPerTexel = 22.0;
// Of which the aperture map's running sums, which a bake of GIS rasters
// alone does without (BakeOptions::apertureMap).
constexpr double kApertureSumBytesPerTexel = 16.0;
constexpr int kDefaultTileSize = 4096;
constexpr int kMinTileSize = 16, kMaxTileSize = 16384;

// The near sweep's reach of a far-field tiled bake by default, in cells.
constexpr int kFarFieldReachCells = 128;
// The shortest near reach R the far field takes is FarFieldOptions::
// resolution cells of the field's smallest cell: there its nearest blocks
// are one cell, and a shorter R would need blocks smaller than a cell
// (docs/baking.md, "Far field").

struct TiledBakeOptions {
  int tileSize = kDefaultTileSize;
  bool halfFloat = true;  // as writeApertureMap
  MapCompression compression = kDefaultMapCompression;
  std::string sourceName;  // aal:source (the DEM's file name)
  // Without a max distance: the far field (far_horizon.h). nearReachM 0:
  // kFarFieldReachCells of the field's smallest cell.
  FarFieldOptions farField;
  // Where a bake that reads the DEM in windows keeps the far field's
  // pyramid, in a file no folder names (HeightPyramid): empty, on the
  // output's file system, which has room for the tiles (the pyramid is
  // 0.083 bytes per DEM texel at the default reach): tiledBakePyramidFolder.
  std::string pyramidFolder;
  // The folder's lock when the caller took it already (aal-bake does, before
  // loading the DEM); else the bake takes it.
  const TiledBakeLock* lock = nullptr;
  // The sky-view factor tiles' creation options and overviews (-co,
  // --overviews); always plain GeoTIFFs, NaN for voids.
  RasterWriteOptions skyViewFactorRaster;
};

// The shortest near reach in metres for `geometry`: far.resolution of its
// smallest cells.
double minimumNearReachM(const Heightfield& geometry, const FarFieldOptions& far);
// Throws InputError, naming --near-reach and the minimum, when
// tiled.farField.nearReachM is given (> 0) and shorter than
// minimumNearReachM. The tools call it before any work; the library takes
// any reach (tests use short ones on small DEMs).
void checkNearReach(const Heightfield& geometry, const TiledBakeOptions& tiled);

struct TiledBakeSummary {
  int tiles = 0;
  int baked = 0;    // baked by this run
  int resumed = 0;  // found finished in the folder and kept
  // DEM samples the tiles' windows read (bakeTiledInBands; the pass over
  // the whole DEM for its checksum not counted).
  uint64_t texelsRead = 0;
};

// Throws std::invalid_argument for options a tiled bake cannot take: a tile
// size outside [kMinTileSize, kMaxTileSize], the ray method, far-field
// options out of range (bakeApertures' range checks apply too).
void checkTiledBakeOptions(const BakeOptions& bake, const TiledBakeOptions& tiled);

// Bakes `field` into `folder` (created if missing; its parent must exist):
// one EXR per tile, written as it finishes, then index.txt. With
// bake.skyViewFactor each tile's SVF too, as a GeoTIFF beside its EXR, and
// before index.txt their mosaic sky_view_factor.vrt
// (sky_view_factor_tiles.h); the DEM must be georeferenced. The folder is
// locked for the whole bake (TiledBakeLock: TiledBakeBusy when another bake
// holds it, before anything is touched). A folder whose index.txt or
// manifest.txt (or, without either, a tile) is of another DEM, other
// options, another tile size or the SVF where it has none (or none where it
// has it) is an InputError saying whose bake it holds;
// nothing is touched. Tiles already in the folder from an interrupted run
// of the same bake are kept when they verify (every pixel decodes and
// matches its checksum), else baked again. bake.progress sees the fraction
// over all tiles; bake.cancel stops between azimuths (BakeCancelled),
// keeping the finished tiles.
// Memory: the DEM (held by the caller) plus ~16 bytes per texel of one tile
// (and, without a max distance, the pyramid: ~0.083 bytes per DEM texel
// at the default reach).
TiledBakeSummary bakeTiled(const Heightfield& field, const BakeOptions& bake,
                           const TiledBakeOptions& tiled, const std::string& folder);

class DemSource;

// The same bake, bit for bit, with the DEM read from `source` one window at
// a time: a tile plus the texels its sweeps read around it (tileHalo) in
// both directions, slid along the tile row (TileWindowReader: the columns
// the next tile shares are kept, only the new ones read; about three reads
// of each DEM texel in all). Memory: two windows (4 bytes per texel of
// about (3 tiles)^2) plus one tile, whatever the DEM's size; the DEM is
// read once more for its checksum (and, without a max distance, its
// pyramid, kept in a file: only the blocks each tile's far field reads are
// in memory, FarFieldWindow). `geometry` is demGeometry of the source. The DEM must have no voids
// (filling them needs all of it): InputError naming gdal_fillnodata.py otherwise, before any tile.
// An existing folder is locked before the checksum pass.
TiledBakeSummary bakeTiledInBands(const DemSource& source, const Heightfield& geometry,
                                  const BakeOptions& bake, const TiledBakeOptions& tiled,
                                  const std::string& folder);

// What bakeTiledInBands holds at its peak, in bytes: the checksum pass's
// row hashes, then the larger of a pass's chunk of rows and one tile's
// window with its bake and far-field blocks (kInMemoryBakeBytesPerTexel per
// window texel). bakeTiledInBands refuses (InputError) before the pass when
// it exceeds the memory available.
double tiledBakeInBandsPeakBytes(const Heightfield& geometry, const BakeOptions& bake,
                                 const TiledBakeOptions& tiled);

// Texels around a tile, in rows and in columns, that its sweeps read: the
// tile size plus the steps of the max distance or, without one, of the far
// field's near reach (+ 3).
int tileHalo(const Heightfield& geometry, const BakeOptions& bake, const TiledBakeOptions& tiled);

// The far field a tiled bake of `geometry` without a max distance uses:
// tiled.farField with nearReachM resolved.
FarFieldOptions resolvedFarField(const Heightfield& geometry, const TiledBakeOptions& tiled);
// The base shift of the pyramid that far field reads.
int tiledBakePyramidShift(const Heightfield& geometry, const TiledBakeOptions& tiled);

// The steps of a tiled bake, for a bake that spreads its tiles over
// processes (preprocess/mpi_tiled_bake.h); bakeTiled and bakeTiledInBands
// run them in one process, in this order.

// What a pass over the whole DEM gives a tiled bake: the heights' checksum
// (heightfieldChecksum's) and, without a max distance, the pyramid.
struct TiledBakeDemPass {
  std::string checksum;
  std::optional<HeightPyramid> pyramid;
};
// The pass, reading `source` in chunks of demPassChunkRows rows, each
// hashed and added to the pyramid on all cores. Voids are an InputError
// (readDemRows); bake.cancel is polled between chunks. The pyramid is kept
// in a file in `pyramidFolder`, in memory if that is empty.
TiledBakeDemPass scanDemForTiledBake(const DemSource& source, const Heightfield& geometry,
                                     const BakeOptions& bake, const TiledBakeOptions& tiled,
                                     const std::string& pyramidFolder = {});
// The parts of the pass, which an MPI bake shares among its ranks.
// The pass's pyramid, empty, in a file in `fileFolder` (in memory if
// empty); nothing for a bake with a max distance.
std::optional<HeightPyramid> emptyTiledBakePyramid(const Heightfield& geometry,
                                                   const BakeOptions& bake,
                                                   const TiledBakeOptions& tiled,
                                                   const std::string& fileFolder = {});
// Where a bake into `folder` keeps its pyramid's file: tiled.pyramidFolder,
// else the folder if it exists and can be written, else its parent if it
// can, else the system's temporary folder.
std::string tiledBakePyramidFolder(const TiledBakeOptions& tiled, const std::string& folder);
// Rows per chunk: about 64 MB, whole block rows of `pyramid`'s finest level
// (when there is one), so that chunks can be read in any order and by any
// process.
int demPassChunkRows(const Heightfield& geometry, const HeightPyramid* pyramid);
// Reads rows [firstRow, firstRow + count) (a chunk), puts their hashes
// (heightRowHash) at rowHashes[firstRow...] and adds their block rows to
// `pyramid` (addBlockRows) when there is one.
void scanDemChunk(const DemSource& source, const Heightfield& geometry, int firstRow, int count,
                  uint64_t* rowHashes, HeightPyramid* pyramid);
// The version 1 heights checksum (heightfield_checksum.h) of the DEM read in
// chunks: serial, for a folder an older bake left unfinished.
std::string legacyDemChecksum(const DemSource& source, const Heightfield& geometry);
// The heights checksum a bake into `folder` records: `checksum`, unless
// the folder's index.txt or manifest.txt records a version 1 checksum
// (isLegacyHeightChecksum) and `legacyChecksum()` (called then only) is
// that: then the version 1 one, so that a bake an older aperture started
// resumes as one bake. Call with the folder's lock held.
std::string tiledBakeChecksum(const std::string& folder, const std::string& checksum,
                              const std::function<std::string()>& legacyChecksum);
// The index (and manifest) of the bake: the whole map's size and attributes.
ApertureTileIndex tiledBakeIndex(const Heightfield& geometry, const std::string& checksum,
                                 const BakeOptions& bake, const TiledBakeOptions& tiled);
// Creates the output folder (not its parents) when missing.
void createTileFolder(const std::string& folder);
// With the folder's lock held: refuses (InputError, touching nothing) a
// folder of another bake, removes dead processes' temporaries and writes
// the manifest unless there is one.
void openTileFolder(const std::string& folder, const ApertureTileIndex& index);
// Whether tile (row, column) is already in the folder, finished and
// verified: its EXR and, when the bake writes the SVF, its SVF GeoTIFF
// (skyViewFactorTileFinished: this tile's items and pixel checksum). A tile
// (EXR or SVF) of another place, DEM or options is an InputError; an
// unreadable one, or one whose pixels do not match their checksum, or one
// without its SVF, is to be baked again.
bool tileFinished(const ApertureTileIndex& index, const std::string& folder, int row, int column);
// The texels of tile (row, column).
TexelWindow tileWindow(const ApertureTileIndex& index, int row, int column);
// Bakes tile (row, column) from `heights` (the whole DEM, or a window that
// holds the tile and tileHalo around it: TileWindowReader) and writes it into the folder (a
// temporary file, renamed), with its SVF GeoTIFF when the bake writes the SVF. `far`: the whole
// DEM's far field, for a bake without a max distance (its options resolvedFarField's).
void bakeTileInto(HeightView heights, const FarField* far, const ApertureTileIndex& index,
                  const BakeOptions& bake, const TiledBakeOptions& tiled, const std::string& folder,
                  int row, int column);
// Once every tile is finished: the SVF mosaic when the bake writes the SVF,
// then index.txt, which says the bake has finished.
void finishTileFolder(const std::string& folder, const ApertureTileIndex& index);

}  // namespace aal
