#include "aperture/preprocess/far_horizon.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/horizon_sweep.h"

namespace aal {

namespace {

// The smallest and largest cell of rows [first, last] (clamped to the DEM),
// the rows' north-south cell among them.
std::pair<double, double> cellRange(const BakeTerrain& terrain, long first, long last) {
  first = std::max(first, 0L);
  last = std::min(last, long(terrain.height - 1));
  double smallest = terrain.cellY, largest = terrain.cellY;
  if (terrain.uniformCellX) first = last = std::min(first, last);
  for (long row = first; row <= last; ++row) {
    smallest = std::min(smallest, terrain.rowCellX[static_cast<size_t>(row)]);
    largest = std::max(largest, terrain.rowCellX[static_cast<size_t>(row)]);
  }
  return {smallest, largest};
}

// The level FarLineMarch starts at for a near reach `reach`, where blocks of
// one cell end at `blockUnit` metres.
int firstShift(double reach, double blockUnit, const HeightPyramid& pyramid) {
  return std::clamp(static_cast<int>(std::floor(std::log2(std::max(reach / blockUnit, 1.0)))),
                    pyramid.baseShift(), pyramid.coarsestShift());
}

}  // namespace

int farFieldBaseShift(const FarFieldOptions& options, double largestCellM) {
  return pyramidBaseShift(options.nearReachM, largestCellM, options.resolution);
}

double farFieldWalkReachM(const FarFieldOptions& options, double largestCellM) {
  return options.nearReachM +
         2.0 * std::ldexp(largestCellM, farFieldBaseShift(options, largestCellM));
}

double farLevelReachM(const FarFieldOptions& options, double largestCellM, int shift) {
  return options.resolution * largestCellM * std::ldexp(2.0, shift) - options.nearReachM;
}

std::string farFieldMethod(const FarFieldOptions& options) {
  char text[160];
  std::snprintf(text, sizeof text, "sweep+far-field(max, reach %.6g m, lines, blocks 1/%d)",
                options.nearReachM, options.resolution);
  return text;
}

FarFieldWindow::FarFieldWindow(const FarField& far, const BakeTerrain& terrain)
    : options_(far.options) {
  const HeightPyramid& pyramid = *far.pyramid;
  if (pyramid.width() != terrain.width || pyramid.height() != terrain.height) {
    throw std::invalid_argument("far field: the pyramid is of another DEM's size");
  }
  // Where the lines that reach the tile start (windowSweepHalo), inside the
  // heights held, and a texel more for a start between texels.
  const TexelWindow& tile = terrain.window;
  const TexelWindow& held = terrain.heights.texels;
  std::tie(smallestCell_, largestCell_) = cellRange(terrain, 0, terrain.height - 1);
  const long halo = windowSweepHalo(terrain, walkReachM()) + 1;
  const long c0 = std::max(long(held.col) - 1, long(tile.col) - halo);
  const long c1 = std::min(long(held.col + held.width), long(tile.col + tile.width - 1) + halo);
  const long r0 = std::max(long(held.row) - 1, long(tile.row) - halo);
  const long r1 = std::min(long(held.row + held.height), long(tile.row + tile.height - 1) + halo);

  const double blockUnit = options_.resolution * largestCell_;
  const auto [startSmallest, startLargest] = cellRange(terrain, r0, r1);
  // x of the start points (FarLineMarch::march): (col - centre) x the start row's cell.
  const auto xAt = [&](long col, bool least) {
    const double dc = double(col) - terrain.centreCol;
    return dc * ((dc < 0) == least ? startLargest : startSmallest);
  };
  const double x0 = xAt(c0, true), x1 = xAt(c1, false);
  for (int shift = firstShift(options_.nearReachM, blockUnit, pyramid);
       shift <= pyramid.coarsestShift(); ++shift) {
    const HeightPyramid::Level& whole = pyramid.level(shift);
    Level level;
    level.shift = shift;
    if (shift == pyramid.coarsestShift()) {
      level.width = whole.width;
      level.height = whole.height;
    } else {
      const double reachM = farLevelReachM(options_, largestCell_, shift);
      const long rows = static_cast<long>(std::ceil(reachM / terrain.cellY)) + 1;
      const long rowLo = std::max(0L, r0 - rows),
                 rowHi = std::min(long(terrain.height - 1), r1 + rows);
      const auto [smallest, largest] = cellRange(terrain, rowLo, rowHi);
      const double xLo = x0 - reachM, xHi = x1 + reachM;
      const double colLo = terrain.centreCol + xLo / (xLo < 0 ? smallest : largest) - 1;
      const double colHi = terrain.centreCol + xHi / (xHi < 0 ? largest : smallest) + 1;
      const long cLo =
          std::clamp(static_cast<long>(std::floor(colLo)), 0L, long(terrain.width - 1));
      const long cHi = std::clamp(static_cast<long>(std::ceil(colHi)), 0L, long(terrain.width - 1));
      level.x0 = static_cast<int>(cLo >> shift);
      level.y0 = static_cast<int>(rowLo >> shift);
      level.width = static_cast<int>(cHi >> shift) - level.x0 + 1;
      level.height = static_cast<int>(rowHi >> shift) - level.y0 + 1;
    }
    level.max.resize(static_cast<size_t>(level.width) * level.height);
    pyramid.readBlocks(shift, level.x0, level.y0, level.width, level.height, level.max.data());
    levels_.push_back(std::move(level));
  }
}

void FarFieldWindow::Level::outside(int bx, int by) const {
  throw std::logic_error("far field: block " + std::to_string(bx) + "," + std::to_string(by) +
                         " of level 2^" + std::to_string(shift) +
                         " lies outside the blocks held for the window");
}

size_t FarFieldWindow::bytes() const {
  size_t total = 0;
  for (const Level& l : levels_) total += l.max.size() * sizeof(float);
  return total;
}

FarLineMarch::FarLineMarch(const FarFieldWindow& far, const BakeTerrain& terrain, double phi)
    : far_(far), terrain_(terrain), ux_(std::cos(phi)), uy_(std::sin(phi)) {}

void FarLineMarch::march(double colF, double rowF, std::vector<float>& distance,
                         std::vector<float>& height) const {
  distance.clear();
  height.clear();
  const BakeTerrain& terrain = terrain_;
  const long startRow = std::clamp(std::lround(rowF), 0L, long(terrain.height - 1));
  const double x0 = (colF - terrain.centreCol) * terrain.rowCellX[startRow];
  const double y0 = terrain.rowY[0] - rowF * terrain.cellY;
  const double reach = far_.options().nearReachM;
  const double smallestCell = far_.smallestCellM();
  const double blockUnit = far_.options().resolution * far_.largestCellM();  // blocks of 1 cell end
  int shift = far_.baseShift();  // the level the march starts at
  double d = 0.5 * double(1 << shift) * smallestCell;
  const FarFieldWindow::Level* level = &far_.level(shift);
  for (;;) {
    while (shift < far_.coarsestShift() && reach + d >= blockUnit * double(2 << shift)) {
      level = &far_.level(++shift);
    }
    const double x = x0 + d * ux_, y = y0 + d * uy_;
    const long r = std::lround((terrain.rowY[0] - y) / terrain.cellY);
    if (r < 0 || r >= terrain.height) break;
    const long c = std::lround(x * terrain.rowInvCellX[r] + terrain.centreCol);
    if (c < 0 || c >= terrain.width) break;
    distance.push_back(static_cast<float>(d));
    height.push_back(level->maxAt(static_cast<int>(c >> shift), static_cast<int>(r >> shift)));
    d += 0.5 * double(1 << shift) * smallestCell;
  }
}

}  // namespace aal
