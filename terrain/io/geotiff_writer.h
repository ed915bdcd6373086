// Float32 GeoTIFF output for per-texel results (sky-view factor, visible
// sky) that GIS tools open next to the DEM they came from.
#pragma once

#include <string>

#include "heightfield.h"

namespace aal {

// Writes width x height floats (row 0 = north, row-major) as a single-band
// float32 GeoTIFF (deflate, floating-point predictor) carrying `geo`:
// geographic grids with GeographicTypeGeoKey geo.epsg (4326 when 0) in
// degrees; projected grids with ProjectedCSTypeGeoKey geo.epsg (user-defined
// when 0) and their linear unit; PixelIsArea with the tie point on the
// north-west corner of texel (0, 0). crs None writes a plain float TIFF.
// The file is written to a temporary name and renamed into place
// (atomic_file.h). Throws std::invalid_argument for sizes outside
// [1, kMaxDemSide], a null `data` or a georeference without finite
// positive steps, std::runtime_error when writing fails.
void writeFloatGeoTiff(const std::string& path, int width, int height, const float* data,
                       const GeoReference& geo);

}  // namespace aal
