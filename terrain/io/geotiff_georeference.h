// Meaning of GeoTIFF tags (GeoTIFF 1.0 spec, OGC 19-008r4): which CRS, where
// texel centres lie, in which units, and the nodata value.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "geotiff_tags.h"
#include "heightfield.h"

namespace aal {

struct GeoTiffGeoreference {
  // crs None for a plain TIFF (no GeoKeys, no placement tags) or when the
  // model type cannot be told (a warning says so). Otherwise origin and step
  // describe texel centres, north-up (stepY > 0); geographic grids in
  // degrees, projected grids in CRS units with linearUnitM.
  GeoReference geo;
  bool southUp = false;  // the file stores rows south to north: flip them
  double zUnitM = 1.0;   // metres per stored height unit (VerticalUnitsGeoKey)
  bool zUnitFromFile = false;
  std::optional<double> nodata;  // from GDAL_NODATA; NaN allowed
};

// Rules: ModelTransformation (no rotation or shear) or ModelPixelScale plus
// the first ModelTiepoint place the grid; GTRasterTypeGeoKey 2 (PixelIsPoint)
// puts the tie point on the centre of its texel, 1 (PixelIsArea, the default)
// on its north-west corner, so texel (0, 0)'s centre is half a pixel in.
// Angular units default to degrees; a projected CRS without linear unit is
// taken as metres (a warning unless it is UTM/UPS). Throws
// InputError("PATH: inconsistent georeferencing: ...") for a geocentric or
// unknown model type, a model type contradicting the CRS keys, GeoKeys
// without placement, tie points without pixel scale, rotated grids, wrong
// value counts, non-finite or zero scales, and unknown unit codes.
GeoTiffGeoreference interpretGeoTiffTags(const std::string& path, const GeoTiffTags& tags,
                                         const std::function<void(const std::string&)>& warn);

}  // namespace aal
