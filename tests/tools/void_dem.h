// The small georeferenced DEM with a void that the tests of aal-bake's GIS
// rasters (openness, anisotropic sky-view factor, sky illumination) bake.
#pragma once

#include <filesystem>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal::test {

// The DEM's declared nodata value.
constexpr float kVoidDemNodata = -9999.0f;

// UTM 16N, square cells of `cellM` metres.
inline GeoReference utm(double cellM) {
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500000;
  geo.originY = 4000000;
  geo.stepX = geo.stepY = cellM;
  return geo;
}

// A 40 x 40 fBm DEM of 30 m cells in UTM 16N with a void of 3 x 2 texels
// at (20, 10), written as dir/dem.tif.
inline std::filesystem::path writeDemWithVoids(const TempDir& dir) {
  SyntheticTerrainOptions s;
  s.width = s.height = 40;
  s.cellSizeM = 30;
  s.featureSizeTexels = 10;
  Heightfield field = makeSyntheticTerrain(s);
  for (int row = 10; row < 12; ++row) {
    for (int col = 20; col < 23; ++col) field.z[field.index(col, row)] = kVoidDemNodata;
  }
  RasterWriteOptions options;
  options.nodata = kVoidDemNodata;
  const std::filesystem::path path = dir.path() / "dem.tif";
  writeFloatGeoTiff(path.string(), 40, 40, field.z.data(), utm(30), options);
  return path;
}

// Whether texel (col, row) of writeDemWithVoids' DEM is its void.
inline bool isVoid(int col, int row) {
  return row >= 10 && row < 12 && col >= 20 && col < 23;
}

}  // namespace aal::test
