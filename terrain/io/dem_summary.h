// What aal-info reports about a DEM beyond its geometry, gathered a band of
// rows at a time so that a DEM of any size costs a band's memory.
#pragma once

#include <cstddef>

#include "aperture/terrain/heightfield.h"

namespace aal {

class DemSource;

struct DemSummary {
  float zMinM = 0, zMaxM = 0;  // over valid (non-void) texels, metres
  size_t voids = 0;            // nodata, masked, NaN or infinite texels
  // Smallest and largest east-west spacing over the rows, metres (equal to
  // cellSizeXM for projected and ungeoreferenced grids).
  double rowCellSizeXMinM = 0, rowCellSizeXMaxM = 0;
};

// Reads every row of `source` (geometry = demGeometry of it) in bands of at
// most `bandBytes` of samples and half the memory available. Throws InputError as loadDem does:
// corrupt data, heights beyond kMaxHeightM, a DEM that is all void.
DemSummary summarizeDem(const DemSource& source, const Heightfield& geometry,
                        size_t bandBytes = size_t{64} << 20);

}  // namespace aal
