#include "geotiff_reader.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "errors.h"
#include "geotiff_georeference.h"
#include "geotiff_tags.h"
#include "image_band.h"

namespace aal {

namespace {

void flipRows(RawDem& dem) {
  const auto width = static_cast<size_t>(dem.width);
  for (int top = 0, bottom = dem.height - 1; top < bottom; ++top, --bottom) {
    std::swap_ranges(dem.z.begin() + static_cast<ptrdiff_t>(top * width),
                     dem.z.begin() + static_cast<ptrdiff_t>((top + 1) * width),
                     dem.z.begin() + static_cast<ptrdiff_t>(bottom * width));
    std::swap_ranges(dem.voidMask.begin() + static_cast<ptrdiff_t>(top * width),
                     dem.voidMask.begin() + static_cast<ptrdiff_t>((top + 1) * width),
                     dem.voidMask.begin() + static_cast<ptrdiff_t>(bottom * width));
  }
}

// OpenImageIO 2.4 sizes its buffer for a strip by RowsPerStrip even when that
// exceeds the image height (values of 2^31 and more it treats as "one
// strip"), and for a tile by the tile size: a hostile file could ask for
// gigabytes before one pixel is read. Refuse layouts whose chunk would be far
// bigger than the image itself.
void checkChunkSize(const std::string& path, const GeoTiffTags& tags) {
  const double pixelBytes =
      tags.samplesPerPixel * std::max(1.0, std::ceil(tags.bitsPerSample / 8.0));
  const double imageBytes =
      pixelBytes * static_cast<double>(tags.width) * static_cast<double>(tags.height);
  const double limit = std::max(256.0 * 1024 * 1024, 2.0 * imageBytes);
  double chunkBytes = 0;
  std::string chunk;
  if (tags.tileWidth > 0 || tags.tileLength > 0) {
    chunkBytes = pixelBytes * tags.tileWidth * tags.tileLength;
    chunk = std::to_string(tags.tileWidth) + " x " + std::to_string(tags.tileLength) + " tiles";
  } else if (tags.rowsPerStrip < 0x80000000u) {
    chunkBytes = pixelBytes * static_cast<double>(tags.width) * tags.rowsPerStrip;
    chunk = "strips of " + std::to_string(tags.rowsPerStrip) + " rows (RowsPerStrip)";
  }
  if (chunkBytes > limit) {
    char size[64];
    std::snprintf(size, sizeof size, "%.3g GB", chunkBytes / 1e9);
    throw InputError(path + ": inconsistent TIFF layout: " + chunk + " for a " +
                     std::to_string(tags.width) + " x " + std::to_string(tags.height) +
                     " image would need " + size + " per chunk");
  }
}

}  // namespace

RawDem readGeoTiff(const std::string& path, const DemLoadOptions& options) {
  const GeoTiffTags tags = readGeoTiffTags(path);
  checkDemSize(path, tags.width, tags.height, options.maxTexels);
  checkChunkSize(path, tags);
  const GeoTiffGeoreference georef = interpretGeoTiffTags(path, tags, options.warn);
  RawDem dem = readImageBand(path, "tiff", georef.nodata, options);
  if (dem.width != tags.width || dem.height != tags.height) {
    throw InputError(path + ": libtiff and OpenImageIO disagree on the size of the image");
  }
  if (georef.southUp) flipRows(dem);
  dem.geo = georef.geo;
  dem.zUnitM = georef.zUnitM;
  dem.zUnitFromFile = georef.zUnitFromFile;
  dem.format = georef.geo.crs == CrsKind::None ? "TIFF" : "GeoTIFF";
  return dem;
}

}  // namespace aal
