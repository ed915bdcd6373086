// Loading a DEM file into a Heightfield: format detection, reading,
// georeferencing to metric spacing, void filling (DESIGN §1, §3).
#pragma once

#include <string>

#include "dem_options.h"
#include "heightfield.h"
#include "raw_dem.h"

namespace aal {

// Reads GeoTIFF/TIFF, SRTM .hgt, ESRI ASCII grid, PNG or OpenEXR (see
// dem_format.h) and returns a heightfield with
// - heights in metres: samples times options.zScale, else the file's
//   vertical unit (feet give 0.3048), else 1;
// - metric spacing: options.cellSizeM (uniform), else from the
//   georeferencing (georeference.h: per-row x spacing on WGS84 for
//   geographic grids), else kDefaultCellSizeM with a warning that names
//   --cell-size and --z-scale;
// - voids (nodata, NaN, +-inf, values beyond float range) flagged in
//   voidMask and filled with the nearest valid height, so z has no NaN.
// Throws InputError("PATH: ...") for every bad input: missing, unreadable,
// truncated or unrecognised files, sizes beyond the limits, non-numeric
// samples, inconsistent georeferencing, a DEM that is all void, and invalid
// overrides. Nothing is returned partially.
Heightfield loadDem(const std::string& path, const DemLoadOptions& options = {});

// The steps of loadDem after reading: scale, georeference, fill. `path`
// names the source in messages and in Heightfield::source. Used by loadDem
// and by the fuzzers.
Heightfield heightfieldFromRaw(RawDem raw, const std::string& path, const DemLoadOptions& options);

}  // namespace aal
