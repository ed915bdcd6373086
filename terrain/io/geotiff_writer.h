// GeoTIFF output, through GDAL, for per-texel results (sky-view factor,
// visible sky, shaded relief) that GIS tools open next to the DEM they came
// from: float32 or 8-bit, one band (grey) or several (RGB, RGBA).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aperture/terrain/heightfield.h"

namespace aal {

struct RasterWriteOptions {
  // A cloud-optimized GeoTIFF (GDAL's COG driver: tiled, overviews, ordered
  // for HTTP range reads) instead of a plain tiled GeoTIFF.
  bool cog = false;
  // The band's nodata value: texels holding it are voids for GIS tools.
  std::optional<double> nodata;
  // GDAL metadata items (NAME, VALUE) of the dataset, in its default domain
  // (the GeoTIFF's GDAL_METADATA tag; gdalinfo lists them): what ties a tiled
  // bake's sky-view factor tile to its place and bake
  // (preprocess/sky_view_factor_tiles.h).
  std::vector<std::pair<std::string, std::string>> metadata;
};

enum class RasterSampleType { Float32, Byte };

// Samples to write: row-major from the northern row, bands interleaved per
// pixel (R, G, B, A, R, ...). 3 bands are tagged RGB, 4 RGB + alpha, so GIS
// tools show them in colour and treat alpha 0 as transparent.
struct RasterImage {
  int width = 0, height = 0, bands = 1;
  RasterSampleType type = RasterSampleType::Float32;
  const void* data = nullptr;
};

// As writeFloatGeoTiff, for any RasterImage (1 to 4 bands; byte samples use
// the horizontal-differencing predictor). options.nodata applies to every
// band.
void writeGeoTiff(const std::string& path, const RasterImage& image, const GeoReference& geo,
                  const RasterWriteOptions& options = {});

// Writes width x height floats (row 0 = north, row-major) as a single-band
// float32 GeoTIFF (DEFLATE with the floating-point predictor, 256-texel
// tiles, BigTIFF when needed, compressed on every core) placed by `geo`: its
// WKT when it has one, else its EPSG code (4326 for a geographic grid
// without one), else a local CRS in its linear unit; PixelIsArea. crs None
// writes a plain float TIFF. The file is written to a temporary name and
// renamed into place (atomic_file.h). Throws std::invalid_argument for sizes
// outside [1, kMaxDemSide], a null `data` or a georeference without finite
// positive steps, std::runtime_error when writing fails.
void writeFloatGeoTiff(const std::string& path, int width, int height, const float* data,
                       const GeoReference& geo, const RasterWriteOptions& options = {});

}  // namespace aal
