// GDAL set-up shared by every reader and writer (docs/dem-input.md): the
// drivers registered once, GDAL's own messages kept off stderr (they reach
// the user inside our errors instead), decoding on every core.
#pragma once

#include <memory>
#include <string>

#include <gdal_priv.h>

#include "aperture/terrain/heightfield.h"

class OGRSpatialReference;

namespace aal {

// Registers GDAL's drivers once per process (thread-safe), sends GDAL's
// error messages to CPLGetLastErrorMsg only (a fatal one, an allocation that
// failed inside GDAL, ends the tool with exit 1 and a message that says
// memory), and sets GDAL_NUM_THREADS to gdalThreads() unless the user set it, so that compressed
// GeoTIFFs decode and encode on every core.
void ensureGdal();

// GDAL's thread count for decoding and encoding: "ALL_CPUS", or fewer under
// a tight ulimit -v (threadsThatFit, terrain/io/memory_budget.h), because
// GDAL 3.6's worker pool waits for ever on a job when some of its threads
// could not start.
std::string gdalThreads();

// `path` opened read-only as a raster by GDAL's GeoTIFF driver alone, or
// null when that driver does not take it (then open it after ensureGdal()).
// Registering all ~200 drivers costs 8 ms at every start, and most DEMs are
// GeoTIFFs (docs/performance.md). Sets up GDAL as ensureGdal() does, but for
// the drivers.
GDALDatasetUniquePtr openGeoTiff(const std::string& path);

// The CRS `geo` names: a copy of its CRS, else its EPSG code; null when it names none
// or OGR cannot read it. Axes in the traditional GIS order (x east, y north).
std::unique_ptr<OGRSpatialReference> spatialReferenceOf(const GeoReference& geo);

// RasterIO's extra argument whose progress callback stops the read (CE_Failure)
// once the interrupt flag is up (terrain/interrupt.h): GDAL calls it block by
// block, so a large read answers Ctrl-C within a block, not at its end.
GDALRasterIOExtraArg interruptibleRead();

// Throws the error of a failed read: Interrupted when the interrupt stopped
// it; when GDAL ran out of memory, a runtime_error that says memory (and the
// limit, memory_budget.h); else InputError "PATH: cannot read its samples
// (truncated or corrupt?): GDAL's message".
[[noreturn]] void throwReadFailure(const std::string& path);

// GDAL's last error message on this thread, or `fallback` when it has none.
std::string gdalLastError(const std::string& fallback = "no details from GDAL");

}  // namespace aal
