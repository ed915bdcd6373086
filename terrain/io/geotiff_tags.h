// The GeoTIFF tags of a TIFF file, as stored, read with libtiff and libgeotiff
// (OpenImageIO 2.4 drops them, DESIGN §11). interpretGeoTiffTags
// (geotiff_georeference.h) gives them meaning.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace aal {

struct GeoTiffTags {
  int64_t width = 0, height = 0;  // of the first image (subimage 0)
  int samplesPerPixel = 1;
  int bitsPerSample = 1;
  // Layout as stored: RowsPerStrip (2^32 - 1 when absent) or tile size.
  uint32_t rowsPerStrip = 0xffffffffu;
  uint32_t tileWidth = 0, tileLength = 0;  // 0 for strip images
  bool hasGeoKeys = false;                 // a GeoKeyDirectory (34735) is present
  // GeoKeys that matter here, when present (codes from the GeoTIFF spec).
  std::optional<int> modelType;              // 1024: 1 projected, 2 geographic, 3 geocentric
  std::optional<int> rasterType;             // 1025: 1 PixelIsArea, 2 PixelIsPoint
  std::optional<int> geographicType;         // 2048: EPSG code of the geographic CRS
  std::optional<int> angularUnits;           // 2054: EPSG unit code
  std::optional<double> angularUnitSizeRad;  // 2055, for user-defined angular units
  std::optional<int> projectedType;          // 3072: EPSG code of the projected CRS
  std::optional<int> linearUnits;            // 3076: EPSG unit code
  std::optional<double> linearUnitSizeM;     // 3077, for user-defined linear units
  std::optional<int> verticalUnits;          // 4099: EPSG unit code of the heights
  std::vector<double> pixelScale;            // 33550 ModelPixelScale (3 values)
  std::vector<double> tiePoints;             // 33922 ModelTiepoint (6 per point)
  std::vector<double> transformation;        // 34264 ModelTransformation (16 values)
  std::optional<std::string> gdalNodata;     // 42113 GDAL_NODATA, an ASCII number
};

// Reads the tags of the first image of a TIFF (classic or BigTIFF). Throws
// InputError("PATH: ...") with libtiff's message when the file is not a
// readable TIFF or its GeoKey directory is corrupt.
GeoTiffTags readGeoTiffTags(const std::string& path);

}  // namespace aal
