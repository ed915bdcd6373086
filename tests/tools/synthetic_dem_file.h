// A synthetic DEM written as a projected float GeoTIFF, for the tools'
// command-line tests (aal-bake's tiled and MPI bakes).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal::test {

// Where the tests place their DEMs: UTM zone 16N with 30 m cells, or
// geographic with 1/1200-degree cells (steps that are not binary fractions).
inline GeoReference testGeoReference(bool geographic) {
  GeoReference geo;
  geo.crs = geographic ? CrsKind::Geographic : CrsKind::Projected;
  geo.epsg = geographic ? 4326 : 32616;
  geo.originX = geographic ? -84.4 : 500000;
  geo.originY = geographic ? 60.0 : 4000000;
  geo.stepX = geo.stepY = geographic ? 1.0 / 1200 : 30;
  return geo;
}

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
  const std::filesystem::path path = dir.path() / ("dem" + std::to_string(seed) + ".tif");
  writeFloatGeoTiff(path.string(), width, height, field.z.data(), testGeoReference(false));
  return path;
}

}  // namespace aal::test
