#include "aperture/preprocess/far_horizon.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace aal {

int farFieldBaseShift(const FarFieldOptions& options, double largestCellM) {
  return pyramidBaseShift(options.nearReachM, largestCellM, options.resolution);
}

std::string farFieldMethod(const FarFieldOptions& options) {
  char text[160];
  std::snprintf(text, sizeof text, "sweep+far-field(max, reach %.6g m, lines, blocks 1/%d)",
                options.nearReachM, options.resolution);
  return text;
}

FarLineMarch::FarLineMarch(const FarField& far, const BakeTerrain& terrain, double phi)
    : far_(far),
      terrain_(terrain),
      ux_(std::cos(phi)),
      uy_(std::sin(phi)),
      smallestCell_(terrain.cellY),
      largestCell_(terrain.cellY) {
  // Once per azimuth: a row's cell per DEM row.
  for (double cellX : terrain.rowCellX) {
    smallestCell_ = std::min(smallestCell_, cellX);
    largestCell_ = std::max(largestCell_, cellX);
  }
}

void FarLineMarch::march(double colF, double rowF, std::vector<float>& distance,
                         std::vector<float>& height) const {
  distance.clear();
  height.clear();
  const HeightPyramid& pyramid = *far_.pyramid;
  const BakeTerrain& terrain = terrain_;
  const long startRow = std::clamp(std::lround(rowF), 0L, long(terrain.height - 1));
  const double x0 = (colF - terrain.centreCol) * terrain.rowCellX[startRow];
  const double y0 = terrain.rowY[0] - rowF * terrain.cellY;
  const double reach = far_.options.nearReachM;
  const double blockUnit = far_.options.resolution * largestCell_;  // where blocks of 1 cell end
  int shift = std::clamp(static_cast<int>(std::floor(std::log2(std::max(reach / blockUnit, 1.0)))),
                         pyramid.baseShift(), pyramid.coarsestShift());
  double d = 0.5 * double(1 << shift) * smallestCell_;
  for (;;) {
    while (shift < pyramid.coarsestShift() && reach + d >= blockUnit * double(2 << shift)) ++shift;
    const double x = x0 + d * ux_, y = y0 + d * uy_;
    const long r = std::lround((terrain.rowY[0] - y) / terrain.cellY);
    if (r < 0 || r >= terrain.height) break;
    const long c = std::lround(x * terrain.rowInvCellX[r] + terrain.centreCol);
    if (c < 0 || c >= terrain.width) break;
    distance.push_back(static_cast<float>(d));
    height.push_back(
        pyramid.level(shift).maxAt(static_cast<int>(c >> shift), static_cast<int>(r >> shift)));
    d += 0.5 * double(1 << shift) * smallestCell_;
  }
}

}  // namespace aal
