// What aal-info reports about a loaded DEM, beyond the Heightfield fields.
#pragma once

#include "heightfield.h"

namespace aal {

struct DemSummary {
  float zMinM = 0, zMaxM = 0;  // over valid (non-void) texels, metres
  // Smallest and largest east-west spacing over the rows, metres (equal to
  // cellSizeXM for projected and ungeoreferenced grids).
  double rowCellSizeXMinM = 0, rowCellSizeXMaxM = 0;
};

DemSummary summarizeDem(const Heightfield& field);

}  // namespace aal
