#include "aperture/terrain/io/dem_summary.h"

#include <algorithm>
#include <limits>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/memory_budget.h"

namespace aal {

DemSummary summarizeDem(const DemSource& source, const Heightfield& geometry, size_t bandBytes) {
  DemSummary s;
  const int width = source.width(), height = source.height();
  const size_t texelBytes = sizeof(float) + sizeof(uint8_t);
  // Half of what is available, so that a band fits beside GDAL's cache.
  if (const auto available = availableMemoryBytes()) {
    bandBytes = std::min<size_t>(bandBytes, *available / 2);
  }
  const int bandRows = static_cast<int>(std::clamp<size_t>(
      bandBytes / (texelBytes * static_cast<size_t>(width)), 1, static_cast<size_t>(height)));
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (int row = 0; row < height; row += bandRows) {
    RawDem band = source.read(0, row, width, std::min(bandRows, height - row));
    s.voids += scaleHeights(band, geometry.zScale, source.path(), row);
    for (size_t i = 0; i < band.z.size(); ++i) {
      if (band.voidMask[i]) continue;
      lo = std::min(lo, band.z[i]);
      hi = std::max(hi, band.z[i]);
    }
  }
  if (!(lo <= hi))
    throw InputError(source.path() + ": every texel is void (nodata); nothing to use");
  s.zMinM = lo;
  s.zMaxM = hi;
  if (geometry.rowCellSizeXM.empty()) {
    s.rowCellSizeXMinM = s.rowCellSizeXMaxM = geometry.cellSizeXM;
  } else {
    const auto [minIt, maxIt] =
        std::minmax_element(geometry.rowCellSizeXM.begin(), geometry.rowCellSizeXM.end());
    s.rowCellSizeXMinM = *minIt;
    s.rowCellSizeXMaxM = *maxIt;
  }
  return s;
}

}  // namespace aal
