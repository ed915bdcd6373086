// GeoTIFF and plain TIFF DEMs: pixels through OpenImageIO (image_band.h),
// georeferencing through libtiff/libgeotiff (geotiff_tags.h,
// geotiff_georeference.h).
#pragma once

#include <string>

#include "dem_options.h"
#include "raw_dem.h"

namespace aal {

// Reads band 1 of the first image (int8..int32, uint8..uint32, float16/32/64;
// strips or tiles; any compression libtiff decodes). format is "GeoTIFF" when
// the file is georeferenced, "TIFF" otherwise. Rows of south-up files are
// flipped so that row 0 is north. Throws InputError("PATH: ...") for files
// that are not readable TIFFs, are truncated or corrupt, exceed the size
// limits, or carry inconsistent georeferencing.
RawDem readGeoTiff(const std::string& path, const DemLoadOptions& options);

}  // namespace aal
