// Loading a DEM file into a Heightfield: format detection, reading,
// georeferencing to metric spacing, void filling (docs/dem-input.md).
#pragma once

#include <string>

#include "aperture/terrain/height_window.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/raw_dem.h"

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

class DemSource;

// A heightfield without heights: size, z scale, metric spacing and
// georeferencing of the DEM `source` opened, as loadDem would give them
// (same checks and warnings). For work on parts of a DEM larger than memory.
Heightfield demGeometry(const DemSource& source, const DemLoadOptions& options);

// Rows [firstRow, firstRow + rows) of the DEM, every column, as a window
// of `geometry` (demGeometry of the same source, which must outlive it: the
// window points to it), z holding those rows in metres. Throws InputError
// when a void falls in them: filling voids needs the whole DEM, so a DEM
// read in parts must have none.
HeightWindow readDemRows(const DemSource& source, const Heightfield& geometry, int firstRow,
                         int rows);
HeightWindow readDemRows(const DemSource&, const Heightfield&&, int, int) = delete;

// Columns [firstColumn, firstColumn + columns) of rows [firstRow, firstRow +
// rows) of the DEM as a window of `geometry`, as readDemRows gives a band:
// z holding those texels row after row. The same InputError for voids.
HeightWindow readDemWindow(const DemSource& source, const Heightfield& geometry, int firstColumn,
                           int firstRow, int columns, int rows);
HeightWindow readDemWindow(const DemSource&, const Heightfield&&, int, int, int, int) = delete;

// Heights of `raw` (the window from firstColumn, firstRow of the DEM at
// `path`) times zScale, in place; non-finite ones flagged as voids (set to
// 0) and counted. Throws InputError naming the texel when a height exceeds
// kMaxHeightM.
size_t scaleHeights(RawDem& raw, double zScale, const std::string& path, int firstRow = 0,
                    int firstColumn = 0);

}  // namespace aal
