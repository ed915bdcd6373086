// The aperture map as a GeoTIFF (aal-bake -o map.tif): the same map as the
// EXR (terrain/io/aperture_map.h) for GIS tools, placed like the DEM. Four
// float32 bands, bent normal x (east), y (north), z (up) and the arc length
// r in radians, each with its description (band_labels.h); GDAL metadata
// items AAL_* carry what the EXR's aal: attributes carry (docs/baking.md,
// "The aperture map as GeoTIFF"). Read through GDAL; aal-render, aal-view
// and aal-relief take it wherever they take the EXR (ApertureMapReader).
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/geotiff_writer.h"

namespace aal {

// Whether `path` names an aperture map GeoTIFF: it ends in .tif or .tiff
// (any case).
bool isGeoTiffPath(const std::string& path);

// Writes `map` as float32 GeoTIFF placed by `geo` (the DEM's, as
// writeFloatGeoTiff places it), with `options`' format, creation options
// and overviews; the bands' labels and the AAL_* items are this map's, and
// AAL_PIXEL_CHECKSUM is the pixel checksum (pixel_checksum.h) of its rows
// of interleaved float32 bands, as RasterIO reads them pixel-interleaved.
// Temporary file, renamed. Throws as writeGeoTiff.
void writeApertureGeoTiff(const std::string& path, const ApertureMap& map, const GeoReference& geo,
                          RasterWriteOptions options = {});

// An aperture map GeoTIFF opened for reading rows.
class ApertureGeoTiff {
 public:
  // Opens `path` with GDAL and reads its header. Throws InputError naming
  // the file when it is missing, not a regular file, not a raster GDAL
  // opens (truncated or corrupt), not four float32 bands, or without the
  // AAL_* items or with malformed ones.
  ApertureGeoTiff(const std::string& path, ApertureMapHeader& header);
  ~ApertureGeoTiff();
  ApertureGeoTiff(ApertureGeoTiff&&) noexcept;
  ApertureGeoTiff& operator=(ApertureGeoTiff&&) noexcept;

  // Rows [firstRow, endRow) as 4 floats per texel into `destination`, rows
  // `rowBytes` apart. Throws InputError when GDAL cannot read them
  // (truncated or corrupt), and with the read that completes the map's rows
  // when they do not match AAL_PIXEL_CHECKSUM.
  void readFloatRows(int firstRow, int endRow, float* destination, size_t rowBytes);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aal
