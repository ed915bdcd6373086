// Loading a DEM file into a Heightfield: format detection, reading,
// georeferencing to metric spacing, void filling (DESIGN §1, §3).
#pragma once

#include <string>

#include "dem_options.h"
#include "heightfield.h"
#include "raw_dem.h"

namespace aal {

// Reads any raster GDAL opens (terrain/io/dem_source.h, docs/dem-input.md)
// and returns a heightfield with
// - heights in metres: samples (after the band's scale and offset) times
//   options.zScale, else the file's vertical unit (feet give 0.3048), else 1;
// - metric spacing: options.cellSizeM (uniform), else from the
//   georeferencing (georeference.h: per-row x spacing on WGS84 for
//   geographic grids), else kDefaultCellSizeM with a warning that names
//   --cell-size and --z-scale;
// - voids (nodata, mask or alpha 0, NaN, +-inf, beyond float range) flagged in
//   voidMask and filled with the nearest valid height, so z has no NaN.
// Throws InputError("PATH: ...") for every bad input: missing, unreadable,
// truncated or unrecognised files, sizes beyond the limits, palette, RGB and
// complex images, inconsistent georeferencing, a DEM that is all void, and invalid
// overrides. Nothing is returned partially.
Heightfield loadDem(const std::string& path, const DemLoadOptions& options = {});

// The steps of loadDem after reading: scale, georeference, fill. `path`
// names the source in messages and in Heightfield::source. Used by loadDem
// and for windows of a DemSource.
Heightfield heightfieldFromRaw(RawDem raw, const std::string& path, const DemLoadOptions& options);

}  // namespace aal
