#include "dem_summary.h"

#include <algorithm>
#include <limits>

namespace aal {

DemSummary summarizeDem(const Heightfield& field) {
  DemSummary s;
  float lo = std::numeric_limits<float>::infinity(), hi = -lo;
  for (size_t i = 0; i < field.z.size(); ++i) {
    if (!field.voidMask.empty() && field.voidMask[i]) continue;
    lo = std::min(lo, field.z[i]);
    hi = std::max(hi, field.z[i]);
  }
  if (lo <= hi) {
    s.zMinM = lo;
    s.zMaxM = hi;
  }
  if (field.rowCellSizeXM.empty()) {
    s.rowCellSizeXMinM = s.rowCellSizeXMaxM = field.cellSizeXM;
  } else {
    const auto [minIt, maxIt] =
        std::minmax_element(field.rowCellSizeXM.begin(), field.rowCellSizeXM.end());
    s.rowCellSizeXMinM = *minIt;
    s.rowCellSizeXMaxM = *maxIt;
  }
  return s;
}

}  // namespace aal
