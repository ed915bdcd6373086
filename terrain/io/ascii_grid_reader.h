// ESRI ASCII grids (.asc): a header of "key value" lines (ncols, nrows,
// xllcorner|xllcenter, yllcorner|yllcenter, cellsize or dx and dy, optional
// NODATA_value; keys in any order, any case) followed by nrows rows of ncols
// numbers, north row first. The CRS comes from a WKT .prj file next to the
// grid, when there is one.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "dem_options.h"
#include "raw_dem.h"

namespace aal {

// Parses a whole grid held in memory; `path` names it in messages. `prjText`
// is the WKT of the sidecar .prj: GEOGCS/GEOGCRS gives a geographic grid in
// degrees, anything else a projected one in the last UNIT's metres (and the
// last EPSG AUTHORITY as its code); without it the grid is taken as
// projected in metres, with a warning if cellsize looks like degrees.
// Samples equal to NODATA_value, nan and inf are voids. Throws
// InputError("PATH: ...") for a missing, duplicated, unknown or non-numeric
// header entry, sizes beyond the limits, a non-numeric sample (naming its
// row and column), too few samples (truncated) or too many.
RawDem parseAsciiGrid(const std::string& path, std::string_view text,
                      const std::optional<std::string>& prjText, const DemLoadOptions& options);

// Reads PATH and its sidecar PATH-without-extension.prj (if present).
RawDem readAsciiGrid(const std::string& path, const DemLoadOptions& options);

}  // namespace aal
