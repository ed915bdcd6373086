// GeoTIFF tiles as one raster for GIS tools: a GDAL VRT mosaic of them
// (a tiled bake's sky-view factor, docs/baking.md), and the check that a
// tile reads back.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace aal {

// What GDAL reads of a raster: its size, bands and whether band 1 holds
// float32 samples.
struct RasterShape {
  int width = 0, height = 0, bands = 0;
  bool float32 = false;
  // The dataset's GDAL metadata items (default domain): NAME -> VALUE.
  std::map<std::string, std::string> metadata;
};

// The shape of the raster at `path` as GDAL opens it; nothing when it is
// not a regular file (a FIFO would block GDAL's open) or GDAL cannot open
// it (missing, truncated, not a raster).
std::optional<RasterShape> readRasterShape(const std::string& path);

// The pixel checksum (pixel_checksum.h) of band 1 of the raster at `path`,
// its samples read as float32 rows (the bytes of each row's floats in
// memory, row 0 first); nothing when it is not a regular file or GDAL
// cannot open it or read every sample.
std::optional<uint64_t> floatRasterChecksum(const std::string& path);

// Writes a VRT at `path` (GDALBuildVRT) that places every file of `tiles`
// (georeferenced GeoTIFFs of one CRS, resolution and band layout) by its
// geotransform, at the finest resolution among them, with their nodata
// and the first tile's band descriptions and units.
// Tiles in the VRT's folder or below are named relative to it, so that the
// folder can be moved. Written to a temporary file and renamed
// (atomic_file.h). Throws std::runtime_error naming the VRT when GDAL fails.
void writeVrtMosaic(const std::string& path, const std::vector<std::string>& tiles);

}  // namespace aal
