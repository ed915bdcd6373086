#include "aperture/preprocess/sky_view_factor_tiles.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <utility>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/band_labels.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/io/pixel_checksum.h"
#include "aperture/terrain/io/raster_mosaic.h"

namespace aal {

namespace fs = std::filesystem;

std::string skyViewFactorTileName(int row, int column) {
  char name[64];
  std::snprintf(name, sizeof name, "svf_%04d_%04d.tif", row, column);
  return name;
}

void checkSkyViewFactorTiles(const Heightfield& geometry, bool skyViewFactor) {
  if (skyViewFactor && geometry.geo.crs == CrsKind::None) {
    throw InputError(
        "--svf: a tiled bake places its sky-view factor tiles and their mosaic by the DEM's "
        "georeferencing, which " +
        (geometry.source.empty() ? std::string("this DEM") : geometry.source) +
        " has not: give the DEM a CRS and geotransform (gdal_translate -a_srs -a_ullr), or "
        "bake it untiled with --svf FILE.tif");
  }
}

std::optional<float> markVoidsAsNodata(std::vector<float>& values, HeightView heights,
                                       const TexelWindow& window) {
  const float nodata = std::numeric_limits<float>::quiet_NaN();
  if (heights.dem->voidCount == 0) return nodata;
  for (size_t i = 0; i < values.size(); ++i) {
    const int col = window.col + static_cast<int>(i % static_cast<size_t>(window.width));
    const int row = window.row + static_cast<int>(i / static_cast<size_t>(window.width));
    if (heights.isVoid(col, row)) values[i] = nodata;
  }
  return nodata;
}

namespace {

// "%.17g": a double in words that reads back as itself.
std::string exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string bakeWords(const ApertureTileIndex& index) {
  const ApertureMapInfo& i = index.map.info;
  return "version " + std::to_string(i.version) + ", azimuths " + std::to_string(i.azimuths) +
         ", method " + i.method + ", edge " + i.edge + ", curvature " + (i.curvature ? "1" : "0") +
         ", refraction " + exact(i.refraction) + ", max-distance " + exact(i.maxDistanceM) +
         ", cell-size " + exact(i.cellSizeX) + "x" + exact(i.cellSizeY) + ", z-scale " +
         exact(i.zScale) + ", tile-size " + std::to_string(index.tileSize);
}

}  // namespace

std::vector<std::pair<std::string, std::string>> skyViewFactorTileItems(
    const ApertureTileIndex& index, int row, int column) {
  return {
      {kSvfTileItem, std::to_string(row) + " " + std::to_string(column)},
      {kSvfTileOriginItem,
       std::to_string(column * index.tileSize) + "," + std::to_string(row * index.tileSize)},
      {kSvfSourceSizeItem,
       std::to_string(index.map.width) + "x" + std::to_string(index.map.height)},
      {kSvfSourceChecksumItem, index.map.info.sourceChecksum},
      {kSvfBakeItem, bakeWords(index)},
  };
}

uint64_t skyViewFactorPixelChecksum(const std::vector<float>& values, int width, int height) {
  PixelChecksum sum(height);
  for (int row = 0; row < height; ++row) {
    sum.addRow(row, values.data() + static_cast<size_t>(row) * width, sizeof(float) * width);
  }
  return sum.value();
}

void writeSkyViewFactorTile(const std::string& folder, const ApertureTileIndex& index, int row,
                            int column, std::vector<float> values, HeightView heights,
                            const TexelWindow& window, const RasterWriteOptions& raster) {
  RasterWriteOptions options = raster;
  options.cog = false;
  // NaN in every tile, so that the mosaic has one nodata value.
  options.nodata = markVoidsAsNodata(values, heights, window);
  options.bandLabels = {skyViewFactorBandLabel()};
  options.metadata = skyViewFactorTileItems(index, row, column);
  options.metadata.emplace_back(kSvfPixelChecksumItem, checksumHex(skyViewFactorPixelChecksum(
                                                           values, window.width, window.height)));
  GeoReference geo = heights.dem->geo;
  geo.originX += window.col * geo.stepX;
  geo.originY -= window.row * geo.stepY;
  writeFloatGeoTiff((fs::path(folder) / skyViewFactorTileName(row, column)).string(), window.width,
                    window.height, values.data(), geo, options);
}

bool skyViewFactorTileFinished(const ApertureTileIndex& index, const std::string& folder, int row,
                               int column) {
  const std::string path = (fs::path(folder) / skyViewFactorTileName(row, column)).string();
  const std::optional<RasterShape> shape = readRasterShape(path);
  if (!shape || shape->width != index.tileWidth(column) || shape->height != index.tileHeight(row) ||
      shape->bands != 1 || !shape->float32) {
    return false;
  }
  const auto item = [&](const char* name) -> std::optional<std::string> {
    const auto found = shape->metadata.find(name);
    if (found == shape->metadata.end()) return std::nullopt;
    return found->second;
  };
  const std::optional<std::string> place = item(kSvfTileItem);
  const std::optional<std::string> pixels = item(kSvfPixelChecksumItem);
  if (!place || !pixels) return false;  // written before tiles carried them
  // What differs, in checkApertureTile's words for an aperture tile, with
  // the item that says so.
  for (const auto& [name, want] : skyViewFactorTileItems(index, row, column)) {
    const std::optional<std::string> have = item(name.c_str());
    if (have == want) continue;
    const std::string what = name == kSvfTileItem || name == kSvfTileOriginItem
                                 ? "its place in the DEM differs"
                             : name == kSvfBakeItem ? "the bake options differ"
                                                    : "the DEM it was baked from differs";
    throw InputError("sky-view factor tile " + path +
                     " does not belong to this tiled bake: " + what + " (" + name + " is '" +
                     have.value_or("") + "', this bake's '" + want + "')");
  }
  const std::optional<uint64_t> expected = parseChecksumHex(*pixels);
  const std::optional<uint64_t> actual = floatRasterChecksum(path);
  return expected && actual && *expected == *actual;
}

void writeSkyViewFactorMosaic(const ApertureTileIndex& index, const std::string& folder) {
  std::vector<std::string> tiles;
  for (int row = 0; row < index.rows(); ++row) {
    for (int column = 0; column < index.columns(); ++column) {
      tiles.push_back((fs::path(folder) / skyViewFactorTileName(row, column)).string());
    }
  }
  writeVrtMosaic((fs::path(folder) / kSkyViewFactorMosaicName).string(), tiles);
}

}  // namespace aal
