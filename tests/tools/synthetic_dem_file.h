// A synthetic DEM written as a projected float GeoTIFF, for the tools'
// command-line tests (aal-bake's tiled and MPI bakes).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "geotiff_writer.h"
#include "run_tool.h"
#include "synthetic.h"

namespace aal::test {

// width x height fBm (30 m cells, features of 24 texels) of `seed`, in UTM
// zone 16N, as DIR/dem<seed>.tif.
inline std::filesystem::path writeSyntheticDem(const TempDir& dir, int width, int height,
                                               uint64_t seed = 1) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 30;
  s.seed = seed;
  s.featureSizeTexels = 24;
  const Heightfield field = makeSyntheticTerrain(s);
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500000;
  geo.originY = 4000000;
  geo.stepX = geo.stepY = 30;
  const std::filesystem::path path = dir.path() / ("dem" + std::to_string(seed) + ".tif");
  writeFloatGeoTiff(path.string(), width, height, field.z.data(), geo);
  return path;
}

}  // namespace aal::test
