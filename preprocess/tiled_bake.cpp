#include "aperture/preprocess/tiled_bake.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/height_pyramid.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/sky_view_factor_tiles.h"
#include "aperture/preprocess/tile_window_reader.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/heightfield_checksum.h"
#include "aperture/terrain/io/memory_budget.h"

namespace aal {

namespace fs = std::filesystem;

TiledBakeLock::TiledBakeLock(const std::string& folder)
    : path_((fs::path(folder) / kTiledBakeLockName).string()) {
  // A bake removes the lock file when it ends, so that a refused or finished
  // bake leaves no file of its own in the user's folder. Another bake may
  // have opened that file before it went: it then holds a lock on a file no
  // longer in the folder, which a third could not see. So a lock counts only
  // while the path still names the locked file; else it is taken again.
  for (int attempt = 0;; ++attempt) {
    fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) {
      throw std::runtime_error("cannot open the lock file " + path_ + ": " + std::strerror(errno));
    }
    // The file stays empty: a refused bake changes nothing in the folder.
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      ::close(fd_);
      fd_ = -1;
      if (error == EWOULDBLOCK) {
        throw TiledBakeBusy("another aal-bake is baking into " + folder + " (it holds " + path_ +
                            "): wait for it to finish and run this command again, or bake into "
                            "another folder");
      }
      throw std::runtime_error("cannot lock " + path_ + ": " + std::strerror(error));
    }
    struct stat held {};
    struct stat named {};
    if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 &&
        held.st_dev == named.st_dev && held.st_ino == named.st_ino) {
      return;
    }
    ::close(fd_);  // the file was removed after it was opened: lock the one there now
    fd_ = -1;
    if (attempt >= 100) throw std::runtime_error("cannot lock " + path_ + ": it keeps changing");
  }
}

TiledBakeLock::~TiledBakeLock() {
  if (fd_ < 0) return;
  // Removed while still locked: see the constructor.
  ::unlink(path_.c_str());
  ::close(fd_);
}

void checkTiledBakeOptions(const BakeOptions& bake, const TiledBakeOptions& tiled) {
  if (tiled.tileSize < kMinTileSize || tiled.tileSize > kMaxTileSize) {
    throw std::invalid_argument("tile size must be in [" + std::to_string(kMinTileSize) + ", " +
                                std::to_string(kMaxTileSize) + "]");
  }
  if (bake.method != BakeMethod::Sweep) {
    throw std::invalid_argument("a tiled bake needs the sweep method");
  }
  const FarFieldOptions& far = tiled.farField;
  if (far.resolution < 1 || far.resolution > 1024 || !(far.nearReachM >= 0.0) ||
      !std::isfinite(far.nearReachM)) {
    throw std::invalid_argument("far field: resolution or near reach out of range");
  }
}

namespace {

// "fbm.tif, 300x200, heights checksum 0123456789abcdef": whose bake it is.
std::string describeDem(const ApertureMapHeader& map) {
  return (map.info.source.empty() ? std::string("a DEM") : map.info.source) + ", " +
         std::to_string(map.info.sourceWidth) + "x" + std::to_string(map.info.sourceHeight) +
         ", heights checksum " + map.info.sourceChecksum;
}

std::string pickAnotherFolder(const std::string& folder) {
  return ": bake into another folder, or delete " + folder + " first";
}

// Throws InputError unless `have`, what the folder's record `name` says, is
// this bake: the same DEM (size, checksum), options and tile size.
void checkSameBake(const std::string& folder, const std::string& name,
                   const ApertureTileIndex& have, const ApertureTileIndex& want) {
  const std::string whose = " (its " + name + ": " + describeDem(have.map) + ")";
  if (have.map.width != want.map.width || have.map.height != want.map.height ||
      have.map.info.sourceChecksum != want.map.info.sourceChecksum) {
    throw InputError(folder + " holds the tiled bake of another DEM" + whose + ", not of " +
                     describeDem(want.map) + pickAnotherFolder(folder));
  }
  // The record describes the whole map as tile (0, 0) of one tile would.
  ApertureTileIndex whole = want;
  whole.tileSize = std::max(want.map.width, want.map.height);
  try {
    checkApertureTile(whole, 0, 0, have.map, folder + "/" + name);
  } catch (const InputError&) {
    throw InputError(folder + " holds a tiled bake of this DEM with other options" + whose +
                     pickAnotherFolder(folder));
  }
  if (have.tileSize != want.tileSize) {
    throw InputError(folder + " holds a tiled bake of this DEM in tiles of " +
                     std::to_string(have.tileSize) + ", not " + std::to_string(want.tileSize) +
                     whose + pickAnotherFolder(folder));
  }
  // Adding the SVF to a bake means sweeping every tile again, as a new bake
  // does; a folder is one command's output (docs/baking.md).
  if (have.skyViewFactor != want.skyViewFactor) {
    throw InputError(folder + " holds a tiled bake of this DEM " +
                     (have.skyViewFactor ? "with" : "without") + " the sky-view factor (--svf)" +
                     whose + pickAnotherFolder(folder));
  }
}

// (row, column) of a file named as apertureTileName names tiles, else nothing.
std::optional<std::pair<int, int>> tileOfName(const std::string& name) {
  int row = -1, column = -1;
  if (std::sscanf(name.c_str(), "tile_%4d_%4d.exr", &row, &column) != 2 || row < 0 || column < 0 ||
      apertureTileName(row, column) != name) {
    return std::nullopt;
  }
  return std::pair{row, column};
}

// (row, column) of a file named as skyViewFactorTileName names SVF tiles.
std::optional<std::pair<int, int>> skyViewFactorTileOfName(const std::string& name) {
  int row = -1, column = -1;
  if (std::sscanf(name.c_str(), "svf_%4d_%4d.tif", &row, &column) != 2 || row < 0 || column < 0 ||
      skyViewFactorTileName(row, column) != name) {
    return std::nullopt;
  }
  return std::pair{row, column};
}

// Throws InputError, having touched nothing, unless the folder is empty of
// bakes or holds this bake's: its index.txt (finished) and manifest.txt
// (started) must describe this bake; a folder with neither (a bake
// interrupted before manifests existed) must have no readable tile of
// another bake.
void checkFolderHoldsThisBake(const std::string& folder, const ApertureTileIndex& want) {
  bool recorded = false;
  for (const char* name : {"index.txt", kTiledBakeManifestName}) {
    if (!fs::exists(fs::path(folder) / name)) continue;
    checkSameBake(folder, name, readApertureTileIndex(folder, name), want);
    recorded = true;
  }
  if (recorded) return;
  std::vector<std::string> tiles;  // in name order: the first tile is named
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (tileOfName(name)) tiles.push_back(name);
  }
  std::sort(tiles.begin(), tiles.end());
  for (const std::string& name : tiles) {
    const std::string path = (fs::path(folder) / name).string();
    std::optional<ApertureMapReader> reader;
    try {
      reader.emplace(path);
    } catch (const InputError&) {
      continue;  // unreadable: nobody's, baked again at its turn
    }
    const auto [row, column] = *tileOfName(name);
    try {
      if (row >= want.rows() || column >= want.columns()) {
        throw InputError("aperture tile " + path + " lies outside this bake");
      }
      checkApertureTile(want, row, column, reader->header(), path);
    } catch (const InputError& e) {
      throw InputError(folder + " holds another tiled bake (its " + name + ": " +
                       describeDem(reader->header()) + "): " + e.what() +
                       pickAnotherFolder(folder));
    }
  }
}

}  // namespace

bool isTiledBakeFileName(const std::string& name) {
  return name == "index.txt" || name == kTiledBakeManifestName || name == kTiledBakeLockName ||
         name == kSkyViewFactorMosaicName || tileOfName(name) || skyViewFactorTileOfName(name);
}

bool tileFinished(const ApertureTileIndex& index, const std::string& folder, int row, int column) {
  const std::string path = (fs::path(folder) / apertureTileName(row, column)).string();
  if (!fs::exists(path)) return false;
  std::optional<ApertureMapReader> reader;
  try {
    reader.emplace(path);
  } catch (const InputError&) {
    return false;  // unreadable: bake it again
  }
  // A tile of another place, DEM or options is refused, not baked over: the
  // folder holds files someone moved or mixed, which are theirs to sort out.
  const auto refuse = [](const InputError& e) {
    return InputError(std::string(e.what()) + ": remove the folder or write to another one");
  };
  try {
    checkApertureTile(index, row, column, reader->header(), path);
  } catch (const InputError& e) {
    throw refuse(e);
  }
  try {
    reader->verify();
  } catch (const InputError&) {
    return false;
  }
  if (!index.skyViewFactor) return true;
  try {
    return skyViewFactorTileFinished(index, folder, row, column);
  } catch (const InputError& e) {
    throw refuse(e);
  }
}

void createTileFolder(const std::string& folder) {
  std::error_code error;
  fs::create_directory(folder, error);
  if (!fs::is_directory(folder)) {
    throw std::runtime_error("cannot create the output folder " + folder +
                             (error ? ": " + error.message() : ""));
  }
}

ApertureTileIndex tiledBakeIndex(const Heightfield& geometry, const std::string& checksum,
                                 const BakeOptions& bake, const TiledBakeOptions& tiled) {
  BakeOptions tile = bake;
  const FarField far{nullptr, resolvedFarField(geometry, tiled)};
  if (!(bake.maxDistanceM > 0.0)) tile.farField = &far;  // its method names the far field
  ApertureTileIndex index;
  index.map.width = geometry.width;
  index.map.height = geometry.height;
  index.map.info = bakeInfo(geometry, tile);
  index.map.info.source = tiled.sourceName;
  index.map.info.sourceChecksum = checksum;
  index.tileSize = tiled.tileSize;
  index.skyViewFactor = bake.skyViewFactor;
  return index;
}

void finishTileFolder(const std::string& folder, const ApertureTileIndex& index) {
  if (index.skyViewFactor) writeSkyViewFactorMosaic(index, folder);
  writeApertureTileIndex(folder, index);
}

void openTileFolder(const std::string& folder, const ApertureTileIndex& index) {
  // Another bake's folder is refused before anything in it is touched.
  checkFolderHoldsThisBake(folder, index);
  // What a killed run left behind; a running bake's temporaries stay.
  removeDeadTemporaries(folder);
  if (!fs::exists(fs::path(folder) / kTiledBakeManifestName)) {
    writeApertureTileIndex(folder, index, kTiledBakeManifestName);
  }
}

TexelWindow tileWindow(const ApertureTileIndex& index, int row, int column) {
  return TexelWindow{column * index.tileSize, row * index.tileSize, index.tileWidth(column),
                     index.tileHeight(row)};
}

void bakeTileInto(HeightView heights, const FarField* far, const ApertureTileIndex& index,
                  const BakeOptions& bake, const TiledBakeOptions& tiled, const std::string& folder,
                  int row, int column) {
  BakeOptions tile = bake;
  if (!(bake.maxDistanceM > 0.0)) tile.farField = far;
  const TexelWindow window = tileWindow(index, row, column);
  BakeResult result = bakeApertureWindow(heights, window, tile);
  ApertureMapInfo& info = result.aperture.info;
  info.source = index.map.info.source;
  info.sourceChecksum = index.map.info.sourceChecksum;
  info.originCol = window.col;
  info.originRow = window.row;
  if (bake.skyViewFactor) {
    writeSkyViewFactorTile(folder, index, row, column, std::move(result.skyViewFactor), heights,
                           window, tiled.skyViewFactorRaster);
  }
  writeApertureMap((fs::path(folder) / apertureTileName(row, column)).string(), result.aperture,
                   tiled.halfFloat, tiled.compression);
}

namespace {

// Gives the heights a tile is baked from: the whole DEM's, or a window of
// it that holds the tile and the terrain its sweeps read (tileHalo).
using TileTerrain = std::function<HeightView(const TexelWindow& tile)>;

// `pyramid`: the whole DEM's, for a bake without a max distance;
// `legacyChecksum`: the DEM's version 1 checksum, which older maps carry
// (tiledBakeChecksum).
TiledBakeSummary bakeTiles(const Heightfield& geometry, const std::string& checksum,
                           const std::function<std::string()>& legacyChecksum,
                           const TileTerrain& terrainFor, const HeightPyramid* pyramid,
                           const BakeOptions& bake, const TiledBakeOptions& tiled,
                           const std::string& folder) {
  checkTiledBakeOptions(bake, tiled);
  checkSkyViewFactorTiles(geometry, bake.skyViewFactor);
  createTileFolder(folder);
  // Held to the end: a second bake into this folder stops here, before it
  // could sweep this one's temporaries or write a tile.
  std::optional<TiledBakeLock> ownLock;
  if (!tiled.lock) ownLock.emplace(folder);
  const ApertureTileIndex index =
      tiledBakeIndex(geometry, tiledBakeChecksum(folder, checksum, legacyChecksum), bake, tiled);
  openTileFolder(folder, index);

  TiledBakeSummary summary;
  summary.tiles = index.rows() * index.columns();
  const double total = static_cast<double>(geometry.texelCount());
  double done = 0;  // texels of finished tiles
  BakeOptions tile = bake;
  const FarField far{pyramid, resolvedFarField(geometry, tiled)};
  for (int row = 0; row < index.rows(); ++row) {
    for (int column = 0; column < index.columns(); ++column) {
      const TexelWindow window = tileWindow(index, row, column);
      const double texels = static_cast<double>(window.texelCount());
      if (tileFinished(index, folder, row, column)) {
        ++summary.resumed;
      } else {
        if (bake.progress) {
          tile.progress = [&](double f) { bake.progress((done + f * texels) / total); };
        }
        bakeTileInto(terrainFor(window), &far, index, tile, tiled, folder, row, column);
        ++summary.baked;
      }
      done += texels;
      if (bake.progress) bake.progress(done / total);
    }
  }
  finishTileFolder(folder, index);
  return summary;
}

}  // namespace

namespace {

// The smallest and largest cell of the field, in metres.
std::pair<double, double> cellRange(const Heightfield& field) {
  double smallest = field.cellSizeYM, largest = field.cellSizeYM;
  for (int row = 0; row < field.height; ++row) {
    smallest = std::min(smallest, field.cellSizeXAtRow(row));
    largest = std::max(largest, field.cellSizeXAtRow(row));
  }
  return {smallest, largest};
}

}  // namespace

int tiledBakePyramidShift(const Heightfield& geometry, const TiledBakeOptions& tiled) {
  const double largest = cellRange(geometry).second;
  return farFieldBaseShift(resolvedFarField(geometry, tiled), largest);
}

double minimumNearReachM(const Heightfield& geometry, const FarFieldOptions& far) {
  return far.resolution * cellRange(geometry).first;
}

void checkNearReach(const Heightfield& geometry, const TiledBakeOptions& tiled) {
  const double reach = tiled.farField.nearReachM;
  const double minimum = minimumNearReachM(geometry, tiled.farField);
  if (!(reach > 0.0) || reach >= minimum * (1.0 - 1e-9)) return;
  std::ostringstream message;
  message << "--near-reach " << reach << " m is shorter than the far field allows: at least "
          << minimum << " m (" << tiled.farField.resolution << " cells of "
          << cellRange(geometry).first
          << " m, where the far field's blocks are one cell, docs/baking.md, \"Far field\"); "
             "give at least "
          << minimum << ", or leave the option out (the default: "
          << kFarFieldReachCells * cellRange(geometry).first << " m)";
  throw InputError(message.str());
}

FarFieldOptions resolvedFarField(const Heightfield& geometry, const TiledBakeOptions& tiled) {
  FarFieldOptions far = tiled.farField;
  if (!(far.nearReachM > 0.0)) far.nearReachM = kFarFieldReachCells * cellRange(geometry).first;
  return far;
}

TiledBakeSummary bakeTiled(const Heightfield& field, const BakeOptions& bake,
                           const TiledBakeOptions& tiled, const std::string& folder) {
  checkTiledBakeOptions(bake, tiled);
  checkSkyViewFactorTiles(field, bake.skyViewFactor);
  std::optional<HeightPyramid> pyramid;
  if (!(bake.maxDistanceM > 0.0))
    pyramid.emplace(buildHeightPyramid(field, tiledBakePyramidShift(field, tiled)));
  return bakeTiles(
      field, heightfieldChecksum(field), [&] { return legacyHeightfieldChecksum(field); },
      [&](const TexelWindow&) { return HeightView(field); }, pyramid ? &*pyramid : nullptr, bake,
      tiled, folder);
}

int tileHalo(const Heightfield& geometry, const BakeOptions& bake, const TiledBakeOptions& tiled) {
  // The lines that reach the tile start within the reach of it
  // (windowSweepHalo; the points beyond a max distance are read, then
  // ignored; TileWindow.* tests the bound).
  const double reach =
      bake.maxDistanceM > 0.0
          ? bake.maxDistanceM
          : farFieldWalkReachM(resolvedFarField(geometry, tiled), cellRange(geometry).second);
  // (Only the positions of the terrain are used: geometry may hold no heights.)
  return windowSweepHalo(prepareBakeTerrain(geometry), reach);
}

std::optional<HeightPyramid> emptyTiledBakePyramid(const Heightfield& geometry,
                                                   const BakeOptions& bake,
                                                   const TiledBakeOptions& tiled,
                                                   const std::string& fileFolder) {
  if (bake.maxDistanceM > 0.0) return std::nullopt;
  return HeightPyramid(geometry.width, geometry.height, tiledBakePyramidShift(geometry, tiled),
                       fileFolder);
}

std::string tiledBakePyramidFolder(const TiledBakeOptions& tiled, const std::string& folder) {
  if (!tiled.pyramidFolder.empty()) return tiled.pyramidFolder;
  // The output's file system has room for the tiles; the folder itself once
  // it exists, else its parent (a new folder is made after the pass), else
  // the system's temporary folder where neither can be written.
  const fs::path out = fs::absolute(fs::path(folder)).lexically_normal();
  std::error_code error;
  for (const fs::path& candidate : {out, out.parent_path()}) {
    if (!candidate.empty() && fs::is_directory(candidate, error) &&
        ::access(candidate.c_str(), W_OK | X_OK) == 0) {
      return candidate.string();
    }
  }
  return fs::temp_directory_path(error).string();
}

int demPassChunkRows(const Heightfield& geometry, const HeightPyramid* pyramid) {
  const int blockRows = pyramid ? 1 << pyramid->baseShift() : 1;
  const size_t rows = (size_t{64} << 20) / (sizeof(float) * static_cast<size_t>(geometry.width));
  const size_t blocks = std::max<size_t>(1, rows / static_cast<size_t>(blockRows));
  return static_cast<int>(
      std::min<size_t>(blocks * blockRows, static_cast<size_t>(geometry.height)));
}

void scanDemChunk(const DemSource& source, const Heightfield& geometry, int firstRow, int count,
                  uint64_t* rowHashes, HeightPyramid* pyramid) {
  const HeightWindow rows = readDemRows(source, geometry, firstRow, count);
  tbb::parallel_invoke(
      [&] {
        tbb::parallel_for(tbb::blocked_range<int>(0, count), [&](const tbb::blocked_range<int>& r) {
          for (int i = r.begin(); i < r.end(); ++i) {
            rowHashes[firstRow + i] = heightRowHash(
                rows.z.data() + static_cast<size_t>(i) * geometry.width, geometry.width);
          }
        });
      },
      [&] {
        if (pyramid) pyramid->addBlockRows(firstRow, rows.z.data(), count);
      });
}

TiledBakeDemPass scanDemForTiledBake(const DemSource& source, const Heightfield& geometry,
                                     const BakeOptions& bake, const TiledBakeOptions& tiled,
                                     const std::string& pyramidFolder) {
  TiledBakeDemPass pass;
  pass.pyramid = emptyTiledBakePyramid(geometry, bake, tiled, pyramidFolder);
  HeightPyramid* pyramid = pass.pyramid ? &*pass.pyramid : nullptr;
  std::vector<uint64_t> rowHashes(static_cast<size_t>(geometry.height));
  const int chunk = demPassChunkRows(geometry, pyramid);
  for (int row = 0; row < geometry.height; row += chunk) {
    scanDemChunk(source, geometry, row, std::min(chunk, geometry.height - row), rowHashes.data(),
                 pyramid);
    if (bake.progress) bake.progress(0.0);
    if (bake.cancel && bake.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
  }
  pass.checksum = rowHashChecksum(geometry.width, geometry.height, rowHashes.data());
  return pass;
}

std::string legacyDemChecksum(const DemSource& source, const Heightfield& geometry) {
  LegacyHeightfieldHasher hasher(geometry.width, geometry.height);
  const int chunk = demPassChunkRows(geometry, nullptr);
  for (int row = 0; row < geometry.height; row += chunk) {
    const HeightWindow rows =
        readDemRows(source, geometry, row, std::min(chunk, geometry.height - row));
    hasher.add(rows.z.data(), rows.z.size());
  }
  return hasher.hex();
}

std::string tiledBakeChecksum(const std::string& folder, const std::string& checksum,
                              const std::function<std::string()>& legacyChecksum) {
  for (const char* name : {"index.txt", kTiledBakeManifestName}) {
    if (!fs::exists(fs::path(folder) / name)) continue;
    std::string recorded;
    try {
      recorded = readApertureTileIndex(folder, name).map.info.sourceChecksum;
    } catch (const std::exception&) {
      return checksum;  // openTileFolder says what is wrong with it
    }
    if (!isLegacyHeightChecksum(recorded)) return checksum;
    return legacyChecksum() == recorded ? recorded : checksum;
  }
  return checksum;
}

namespace {

// About what FarFieldWindow holds for a tile whose sweeps read `side`
// texels square: on each level, the window's blocks and those within the
// distance the level is read to (its bound without the skew of geographic
// rows).
double farFieldWindowBytes(const Heightfield& geometry, const TiledBakeOptions& tiled,
                           double side) {
  const FarFieldOptions far = resolvedFarField(geometry, tiled);
  const auto [smallest, largest] = cellRange(geometry);
  const int base = tiledBakePyramidShift(geometry, tiled);
  double bytes = 0.0;
  for (int shift = base;; ++shift) {
    const double block = std::ldexp(1.0, shift);
    const double levelW = std::ceil(geometry.width / block),
                 levelH = std::ceil(geometry.height / block);
    const double reachM = farLevelReachM(far, largest, shift);
    if (reachM > 0.0) {
      const double blocks = (side + 2.0 * reachM / smallest) / block + 3.0;
      bytes += sizeof(float) * std::min(levelW, blocks) * std::min(levelH, blocks);
    }
    if (levelW <= 1.0 && levelH <= 1.0) break;
  }
  return bytes;
}

}  // namespace

double tiledBakeInBandsPeakBytes(const Heightfield& geometry, const BakeOptions& bake,
                                 const TiledBakeOptions& tiled) {
  const double width = geometry.width, height = geometry.height;
  const double rowHashes = sizeof(uint64_t) * height;
  // A chunk is read as samples and void mask, then held as heights.
  const double chunkRows = demPassChunkRows(geometry, nullptr);
  const double chunk = chunkRows * width * (2 * sizeof(float) + 1);
  const double side =
      std::min(width, double(tiled.tileSize) + 2.0 * tileHalo(geometry, bake, tiled));
  double window = side * std::min(height, side) * (sizeof(float) + 1 + kInMemoryBakeBytesPerTexel);
  // The far field's pyramid is in a file; a tile holds the blocks it reads.
  if (!(bake.maxDistanceM > 0.0)) window += farFieldWindowBytes(geometry, tiled, side);
  return rowHashes + std::max(chunk, window);
}

TiledBakeSummary bakeTiledInBands(const DemSource& source, const Heightfield& geometry,
                                  const BakeOptions& bake, const TiledBakeOptions& tiled,
                                  const std::string& folder) {
  checkTiledBakeOptions(bake, tiled);
  checkSkyViewFactorTiles(geometry, bake.skyViewFactor);
  // Refused with the numbers before the checksum pass allocates anything.
  requireMemory(source.path(), tiledBakeInBandsPeakBytes(geometry, bake, tiled),
                "a tiled bake read in windows (" + std::to_string(tiled.tileSize) +
                    "-texel tiles, each with the texels its sweeps read around it)",
                "give a smaller --tile-size (or a shorter --max-distance), or allow more memory "
                "(AAL_MEMORY_LIMIT)");
  // An existing folder is locked before the checksum pass, so that a busy
  // one fails at once (bakeTiles creates and locks a new one).
  std::optional<TiledBakeLock> ownLock;
  TiledBakeOptions locked = tiled;
  if (!locked.lock && fs::is_directory(folder)) locked.lock = &ownLock.emplace(folder);
  TiledBakeDemPass pass =
      scanDemForTiledBake(source, geometry, bake, tiled, tiledBakePyramidFolder(tiled, folder));
  TileWindowReader reader(source, geometry, tileHalo(geometry, bake, tiled));
  TiledBakeSummary summary = bakeTiles(
      geometry, pass.checksum, [&] { return legacyDemChecksum(source, geometry); },
      [&](const TexelWindow& tile) -> HeightView { return reader.windowFor(tile); },
      pass.pyramid ? &*pass.pyramid : nullptr, bake, locked, folder);
  summary.texelsRead = reader.texelsRead();
  return summary;
}

}  // namespace aal
