// One band of an image file read through OpenImageIO, as DEM samples.
#pragma once

#include <optional>
#include <string>

#include "dem_options.h"
#include "raw_dem.h"

namespace aal {

// Reads channel 0 of subimage 0 (COG overviews and extra EXR parts are
// ignored) with the OpenImageIO reader named `oiioFormat` ("tiff", "png",
// "openexr"; no other reader is tried). Integer samples are read in the
// file's own type and converted here, because OpenImageIO 2.4 rescales
// integers to [0, 1] when asked for float (DESIGN §11). Samples equal to
// `nodata` (compared in the file's sample type), NaN and +-inf become voids.
// Fills width, height, z, voidMask and sampleType of the result; warns when
// the image has more than one channel. Throws InputError("PATH: ...") when
// the file cannot be opened or decoded, is a volume, has an unsupported
// sample type, or exceeds the size limits.
RawDem readImageBand(const std::string& path, const std::string& oiioFormat,
                     std::optional<double> nodata, const DemLoadOptions& options);

}  // namespace aal
