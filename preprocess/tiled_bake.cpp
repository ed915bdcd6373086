#include "tiled_bake.h"

#include <algorithm>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "atomic_file.h"
#include "bake_terrain.h"
#include "dem_loader.h"
#include "dem_source.h"
#include "errors.h"
#include "heightfield_checksum.h"
#include "horizon_sweep.h"

namespace aal {

namespace fs = std::filesystem;

void checkTiledBakeOptions(const BakeOptions& bake, const TiledBakeOptions& tiled) {
  if (tiled.tileSize < kMinTileSize || tiled.tileSize > kMaxTileSize) {
    throw std::invalid_argument("tile size must be in [" + std::to_string(kMinTileSize) + ", " +
                                std::to_string(kMaxTileSize) + "]");
  }
  if (bake.method != BakeMethod::Sweep) {
    throw std::invalid_argument("a tiled bake needs the sweep method");
  }
  if (!(bake.maxDistanceM > 0.0)) {
    throw std::invalid_argument(
        "a tiled bake needs a max distance (each tile sees the terrain "
        "within it)");
  }
  if (bake.skyViewFactor) {
    throw std::invalid_argument("a tiled bake writes no sky-view factor");
  }
}

namespace {

// Throws InputError when the folder's index (from a finished run) is not
// that of this bake.
void checkExistingIndex(const std::string& folder, const ApertureTileIndex& want) {
  if (!fs::exists(fs::path(folder) / "index.txt")) return;
  const ApertureTileIndex have = readApertureTileIndex(folder);
  // The index describes the whole map as tile (0, 0) of one tile would.
  ApertureTileIndex whole = want;
  whole.tileSize = std::max(want.map.width, want.map.height);
  try {
    checkApertureTile(whole, 0, 0, have.map, folder + "/index.txt");
  } catch (const InputError&) {
    throw InputError(folder +
                     " holds a finished tiled bake of another DEM or with other "
                     "options: remove it or write to another folder");
  }
  if (have.tileSize != want.tileSize) {
    throw InputError(folder + " holds a tiled bake with tiles of " + std::to_string(have.tileSize) +
                     ", not " + std::to_string(want.tileSize) +
                     ": remove it or write to another folder");
  }
}

// Whether tile (row, column) is already in the folder, finished and
// readable. A tile of another bake is an InputError; an unreadable one is
// baked again.
bool tileFinished(const ApertureTileIndex& index, const std::string& folder, int row, int column) {
  const std::string path = (fs::path(folder) / apertureTileName(row, column)).string();
  if (!fs::exists(path)) return false;
  std::optional<ApertureMapReader> reader;
  try {
    reader.emplace(path);
  } catch (const InputError&) {
    return false;  // unreadable: bake it again
  }
  try {
    checkApertureTile(index, row, column, reader->header(), path);
  } catch (const InputError& e) {
    throw InputError(std::string(e.what()) + ": remove the folder or write to another one");
  }
  // Every row must decode.
  const int width = reader->header().width, height = reader->header().height;
  constexpr int kRows = 64;
  std::vector<uint16_t> rows(static_cast<size_t>(width) * kRows * 4);
  try {
    for (int y = 0; y < height; y += kRows) {
      reader->readHalfRows(y, std::min(height, y + kRows), rows.data());
    }
  } catch (const InputError&) {
    return false;
  }
  return true;
}

}  // namespace

namespace {

// Gives the field a tile row is baked from: the whole DEM, or a band of its
// rows that holds the tile row and the terrain within the max distance.
using TileRowTerrain = std::function<const Heightfield&(int firstRow, int rows)>;

TiledBakeSummary bakeTiles(const Heightfield& geometry, const std::string& checksum,
                           const TileRowTerrain& terrainFor, const BakeOptions& bake,
                           const TiledBakeOptions& tiled, const std::string& folder) {
  checkTiledBakeOptions(bake, tiled);
  std::error_code error;
  fs::create_directory(folder, error);
  if (!fs::is_directory(folder)) {
    throw std::runtime_error("cannot create the output folder " + folder +
                             (error ? ": " + error.message() : ""));
  }
  // What a killed run left behind; a running bake's temporaries stay.
  removeDeadTemporaries(folder);

  ApertureTileIndex index;
  index.map.width = geometry.width;
  index.map.height = geometry.height;
  index.map.info = bakeInfo(geometry, bake);
  index.map.info.source = tiled.sourceName;
  index.map.info.sourceChecksum = checksum;
  index.tileSize = tiled.tileSize;
  checkExistingIndex(folder, index);

  TiledBakeSummary summary;
  summary.tiles = index.rows() * index.columns();
  const double total = static_cast<double>(geometry.texelCount());
  double done = 0;  // texels of finished tiles
  BakeOptions tile = bake;
  for (int row = 0; row < index.rows(); ++row) {
    const Heightfield* field = nullptr;  // read when a tile of this row needs baking
    for (int column = 0; column < index.columns(); ++column) {
      const TexelWindow window{column * tiled.tileSize, row * tiled.tileSize,
                               index.tileWidth(column), index.tileHeight(row)};
      const double texels = static_cast<double>(window.texelCount());
      if (tileFinished(index, folder, row, column)) {
        ++summary.resumed;
      } else {
        if (bake.progress) {
          tile.progress = [&](double f) { bake.progress((done + f * texels) / total); };
        }
        if (field == nullptr) field = &terrainFor(window.row, window.height);
        BakeResult result = bakeApertureWindow(*field, window, tile);
        ApertureMapInfo& info = result.aperture.info;
        info.source = index.map.info.source;
        info.sourceChecksum = index.map.info.sourceChecksum;
        info.originCol = window.col;
        info.originRow = window.row;
        writeApertureMap((fs::path(folder) / apertureTileName(row, column)).string(),
                         result.aperture, tiled.halfFloat, tiled.compression);
        ++summary.baked;
      }
      done += texels;
      if (bake.progress) bake.progress(done / total);
    }
  }
  writeApertureTileIndex(folder, index);
  return summary;
}

}  // namespace

TiledBakeSummary bakeTiled(const Heightfield& field, const BakeOptions& bake,
                           const TiledBakeOptions& tiled, const std::string& folder) {
  checkTiledBakeOptions(bake, tiled);
  return bakeTiles(
      field, heightfieldChecksum(field), [&](int, int) -> const Heightfield& { return field; },
      bake, tiled, folder);
}

int bandHaloRows(const Heightfield& geometry, const BakeOptions& bake, int tileSize) {
  // Every line that reaches the tile is walked from stepsCovering(max
  // distance) steps before the tile to its far side, moving by up to one row
  // a step: lines advancing by columns drift up to the tile's width plus
  // those steps in rows (the points beyond the max distance are read, then
  // ignored). The slopes reach one row further, the interpolation one more.
  return detail::stepsCovering(prepareBakeTerrain(geometry), bake.maxDistanceM) + tileSize + 3;
}

TiledBakeSummary bakeTiledInBands(const DemSource& source, const Heightfield& geometry,
                                  const BakeOptions& bake, const TiledBakeOptions& tiled,
                                  const std::string& folder) {
  checkTiledBakeOptions(bake, tiled);
  // One pass for the DEM's checksum (and its voids, refused before any tile).
  HeightfieldHasher hasher(geometry.width, geometry.height);
  const int chunk =
      std::max(1, static_cast<int>((size_t{64} << 20) / (sizeof(float) * geometry.width)));
  for (int row = 0; row < geometry.height; row += chunk) {
    const Heightfield rows =
        readDemRows(source, geometry, row, std::min(chunk, geometry.height - row));
    hasher.add(rows.z.data(), rows.z.size());
    if (bake.progress) bake.progress(0.0);
    if (bake.cancel && bake.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
  }
  const int halo = bandHaloRows(geometry, bake, tiled.tileSize);
  Heightfield band;
  return bakeTiles(
      geometry, hasher.hex(),
      [&](int firstRow, int rows) -> const Heightfield& {
        const int top = std::max(0, firstRow - halo);
        const int bottom = std::min(geometry.height, firstRow + rows + halo);
        band = Heightfield{};  // free the previous band first
        band = readDemRows(source, geometry, top, bottom - top);
        return band;
      },
      bake, tiled, folder);
}

}  // namespace aal
