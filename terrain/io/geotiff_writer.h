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

// What a band is, for GIS tools: GDALSetDescription's text (QGIS and
// gdalinfo show it as the band's name) and its unit (GDALSetUnitType; "" for
// none).
struct RasterBandLabel {
  std::string description;
  std::string unit;
};

struct RasterWriteOptions {
  // A cloud-optimized GeoTIFF (GDAL's COG driver: tiled, overviews, ordered
  // for HTTP range reads; -of COG) instead of a plain tiled GeoTIFF (-of
  // GTiff).
  bool cog = false;
  // GDAL creation options, "KEY=VALUE" each, as gdal_translate's -co: given
  // to the driver after our defaults, so that they override them (a plain
  // GeoTIFF: COMPRESS=DEFLATE, PREDICTOR=3 for floats or 2 for bytes,
  // TILED=YES, BIGTIFF=IF_SAFER, NUM_THREADS, INTERLEAVE=BAND for several
  // float bands; a COG: COMPRESS=DEFLATE,
  // PREDICTOR=YES, RESAMPLING=AVERAGE, BIGTIFF=IF_SAFER, NUM_THREADS; and
  // for floats compressed with DEFLATE, ZLEVEL=1, a COG's LEVEL=1).
  // checkCreationOptions tells which the driver does not know.
  std::vector<std::string> creationOptions;
  // Internal overviews in a plain GeoTIFF, averaged (a COG always has
  // them): halvings until the smallest fits one 256-texel tile.
  bool overviews = false;
  // The band's nodata value: texels holding it are voids for GIS tools.
  // The tools' float outputs give NaN.
  std::optional<double> nodata;
  // Per band, from band 1; bands past the end are left unlabelled.
  std::vector<RasterBandLabel> bandLabels;
  // GDAL metadata items (NAME, VALUE) of the dataset, in its default domain
  // (the GeoTIFF's GDAL_METADATA tag; gdalinfo lists them): what ties a tiled
  // bake's sky-view factor tile to its place and bake
  // (preprocess/sky_view_factor_tiles.h).
  std::vector<std::pair<std::string, std::string>> metadata;
};

// Throws InputError, with GDAL's words for each, when `options` holds a
// creation option that is not KEY=VALUE, or one the driver (GTiff, or COG
// for options.cog) does not know or whose value it does not take
// (GDALValidateCreationOptions): checked before a bake, not after it.
void checkCreationOptions(const RasterWriteOptions& options);

enum class RasterSampleType { Float32, Byte };

// Samples to write: row-major from the northern row, bands interleaved per
// pixel (R, G, B, A, R, ...). Bytes in 3 bands are tagged RGB, in 4 RGB +
// alpha, so GIS tools show them in colour and treat alpha 0 as
// transparent; float bands are untagged values (up to 4).
struct RasterImage {
  int width = 0, height = 0, bands = 1;
  RasterSampleType type = RasterSampleType::Float32;
  const void* data = nullptr;
};

// As writeFloatGeoTiff, for any RasterImage (1 to 4 bands; byte samples use
// the horizontal-differencing predictor). options.nodata applies to every
// band. Every file carries TIFFTAG_SOFTWARE = softwareName()
// (terrain/version.h).
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
