#include "aperture/preprocess/sky_view_factor_tiles.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <utility>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/geotiff_writer.h"
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

std::optional<float> markVoidsAsNodata(std::vector<float>& values, const Heightfield& field,
                                       const TexelWindow& window) {
  if (field.voidCount == 0 && !field.nodata) return std::nullopt;
  const bool fits = field.nodata && std::isfinite(static_cast<float>(*field.nodata));
  const float nodata =
      fits ? static_cast<float>(*field.nodata) : std::numeric_limits<float>::quiet_NaN();
  for (size_t i = 0; i < values.size(); ++i) {
    const int col = window.col + static_cast<int>(i % static_cast<size_t>(window.width));
    const int row = window.row + static_cast<int>(i / static_cast<size_t>(window.width));
    if (field.isVoid(col, row)) values[i] = nodata;
  }
  return nodata;
}

void writeSkyViewFactorTile(const std::string& path, std::vector<float> values,
                            const Heightfield& field, const TexelWindow& window) {
  RasterWriteOptions options;
  // The same nodata value in every tile, so that the mosaic has one.
  if (const std::optional<float> nodata = markVoidsAsNodata(values, field, window)) {
    options.nodata = *nodata;
  }
  GeoReference geo = field.geo;
  geo.originX += window.col * geo.stepX;
  geo.originY -= window.row * geo.stepY;
  writeFloatGeoTiff(path, window.width, window.height, values.data(), geo, options);
}

bool skyViewFactorTileFinished(const ApertureTileIndex& index, const std::string& folder, int row,
                               int column) {
  const fs::path path = fs::path(folder) / skyViewFactorTileName(row, column);
  if (!fs::exists(path)) return false;
  const std::optional<RasterShape> shape = readRasterShape(path.string());
  return shape && shape->width == index.tileWidth(column) &&
         shape->height == index.tileHeight(row) && shape->bands == 1 && shape->float32;
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
