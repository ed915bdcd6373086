#include "aperture/preprocess/far_horizon.h"

#include <algorithm>
#include <bit>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include <tbb/parallel_for.h>

#include "aperture/preprocess/far_merge.h"
#include "aperture/preprocess/horizon_sweep.h"

namespace aal {

double farMarchStartM(const FarFieldOptions& options, double smallestCellM, double largestCellM) {
  // Start nearer than the reach by the lattice's spacing, so the far march
  // never begins beyond what the near sweep covered.
  const double slack = options.spacing * std::numbers::sqrt2 * largestCellM;
  return std::max(options.nearReachM - slack, smallestCellM);
}

int farFieldBaseShift(const FarFieldOptions& options, double smallestCellM, double largestCellM) {
  return pyramidBaseShift(farMarchStartM(options, smallestCellM, largestCellM), largestCellM,
                          options.resolution);
}

std::string farFieldMethod(const FarFieldOptions& options) {
  char text[160];
  std::snprintf(text, sizeof text, "sweep+far-field(%s, reach %.6g m, lattice %d, blocks 1/%d)",
                options.meanHeights ? "mean" : "max", options.nearReachM, options.spacing,
                options.resolution);
  std::string method = text;
  if (options.maxOfCorners) method.insert(method.size() - 1, ", max of corners");
  return method;
}

FarHorizons::FarHorizons(const FarField& far, const BakeTerrain& terrain, double phi,
                         double curvature, bool clampEdge)
    : far_(far),
      terrain_(terrain),
      smallestCell_(terrain.cellY),
      largestCell_(terrain.cellY),
      ux_(std::cos(phi)),
      uy_(std::sin(phi)),
      curvature_(curvature),
      clampEdge_(clampEdge) {
  // Once per azimuth, not per lattice point: a row's cell per DEM row.
  for (double cellX : terrain.rowCellX) {
    smallestCell_ = std::min(smallestCell_, cellX);
    largestCell_ = std::max(largestCell_, cellX);
  }
  const TexelWindow& w = terrain.window;
  const int g = far.options.spacing;
  // A power of two (the default 16) divides by a shift: that is once or
  // twice per texel and azimuth (4 % of a tiled bake's CPU time at 4096²).
  spacingShift_ = (g > 0 && (g & (g - 1)) == 0) ? std::countr_zero(unsigned(g)) : -1;
  originCol_ = w.col;
  originRow_ = w.row;
  // One point past the window's last texel on each axis, so every texel
  // lies inside a cell of four points.
  columns_ = (w.width - 1) / g + 2;
  rows_ = (w.height - 1) / g + 2;
  points_.resize(static_cast<size_t>(columns_) * rows_);
  tbb::parallel_for(0, rows_, [&](int j) {
    for (int i = 0; i < columns_; ++i) {
      Point& p = points_[static_cast<size_t>(j) * columns_ + i];
      p = march(terrain, originCol_ + i * g, originRow_ + j * g);
      p.along = p.t + p.x * ux_ + p.y * uy_;
    }
  });
  // A texel of a cell is at most spacing * sqrt 2 cells from each of its
  // points along u: its distance to their samples is within that of theirs.
  const double slack = g * std::numbers::sqrt2 * largestCell_;
  bounds_.resize(static_cast<size_t>(columns_ - 1) * (rows_ - 1));
  for (int j = 0; j + 1 < rows_; ++j) {
    for (int i = 0; i + 1 < columns_; ++i) {
      const Point* p = &points_[static_cast<size_t>(j) * columns_ + i];
      double z = detail::kNoHorizon, nearest = std::numeric_limits<double>::infinity(),
             farthest = 0.0;
      for (const Point* q : {p, p + 1, p + columns_, p + columns_ + 1}) {
        if (!(q->t > 0.0)) continue;
        z = std::max(z, q->z);
        nearest = std::min(nearest, q->t);
        farthest = std::max(farthest, q->t);
      }
      CellBound& b = bounds_[static_cast<size_t>(j) * (columns_ - 1) + i];
      const Point* corners[4] = {p, p + 1, p + columns_, p + columns_ + 1};
      for (int k = 0; k < 4; ++k) {
        b.along[k] =
            corners[k]->t > 0.0 ? corners[k]->along : -std::numeric_limits<double>::infinity();
        b.z4[k] = corners[k]->z;
      }
      b.z = z;
      b.invNear = 1.0 / std::max(nearest - slack, 0.5 * smallestCell_);
      b.invFar = 1.0 / (farthest + slack);
    }
  }
}

double FarHorizons::cellBound(const CellBound& c, double z) const {
  if (c.z <= detail::kNoHorizon) return detail::kNoHorizon;
  // (Z - z) / t - k t over the cell's texels and samples, without the drop.
  const double rise = c.z - z;
  return rise * (rise >= 0.0 ? c.invNear : c.invFar);
}

double FarHorizons::mergedTangent(int col, int row, double z, double nearTangent) const {
  if (!clampEdge_) {
    const int i = latticeIndex(col - originCol_), j = latticeIndex(row - originRow_);
    if (cellBound(bounds_[static_cast<size_t>(j) * (columns_ - 1) + i], z) <= nearTangent) {
      return nearTangent;
    }
  }
  return std::max(nearTangent, tangentAt(col, row, z));
}

FarHorizons::Point FarHorizons::march(const BakeTerrain& terrain, int col, int row) const {
  const HeightPyramid& pyramid = *far_.pyramid;
  const FarFieldOptions& o = far_.options;
  // Lattice points past the DEM's last row or column march from its edge.
  col = std::min(col, terrain.width - 1);
  row = std::min(row, terrain.height - 1);
  const HeightView& heights = terrain.heights;
  // The height the best sample is chosen for: the point's own (from the
  // finest level where it is not in memory).
  const double zRef = heights.holds(col, row)
                          ? heights.at(col, row)
                          : pyramid.level(pyramid.baseShift())
                                .meanAt(col >> pyramid.baseShift(), row >> pyramid.baseShift());

  const double smallest = smallestCell_, largest = largestCell_;
  double d = farMarchStartM(o, smallest, largest);
  const double x0 = terrain.x(col, row), y0 = terrain.y(row);
  const double rowY0 = terrain.rowY[0];
  const double blockUnit = o.resolution * largest;  // distance where blocks of 1 cell end

  int shift = std::clamp(static_cast<int>(std::floor(std::log2(std::max(d / blockUnit, 1.0)))),
                         pyramid.baseShift(), pyramid.coarsestShift());
  Point best;
  best.x = x0;
  best.y = y0;
  double bestTangent = -std::numeric_limits<double>::infinity();
  bool inside = false;
  double lastZ = 0.0, lastD = 0.0;
  for (;;) {
    while (shift < pyramid.coarsestShift() && d >= blockUnit * double(2 << shift)) ++shift;
    const double x = x0 + d * ux_, y = y0 + d * uy_;
    const double rowF = (rowY0 - y) / terrain.cellY;
    const long r = std::lround(rowF);
    if (r < 0 || r >= terrain.height) break;
    const double colF = x * terrain.rowInvCellX[r] + terrain.centreCol;
    const long c = std::lround(colF);
    if (c < 0 || c >= terrain.width) break;
    const HeightPyramid::Level& level = pyramid.level(shift);
    double z;
    if (!o.meanHeights) {
      z = level.maxAt(static_cast<int>(c >> shift), static_cast<int>(r >> shift));
    } else {
      // Block means are at block centres: bilinear between the four around.
      const double size = double(1 << shift);
      const double bx = std::clamp((colF + 0.5) / size - 0.5, 0.0, double(level.width - 1));
      const double by = std::clamp((rowF + 0.5) / size - 0.5, 0.0, double(level.height - 1));
      const int x0i = std::min(static_cast<int>(bx), std::max(level.width - 2, 0));
      const int y0i = std::min(static_cast<int>(by), std::max(level.height - 2, 0));
      const int x1i = std::min(x0i + 1, level.width - 1), y1i = std::min(y0i + 1, level.height - 1);
      const double tx = bx - x0i, ty = by - y0i;
      const double top =
          level.meanAt(x0i, y0i) + (level.meanAt(x1i, y0i) - level.meanAt(x0i, y0i)) * tx;
      const double bottom =
          level.meanAt(x0i, y1i) + (level.meanAt(x1i, y1i) - level.meanAt(x0i, y1i)) * tx;
      z = top + (bottom - top) * ty;
    }
    const double tangent = (z - zRef) / d - curvature_ * d;
    if (tangent > bestTangent) {
      bestTangent = tangent;
      best.z = z;
      best.t = d;
    }
    inside = true;
    lastZ = z;
    lastD = d;
    d += 0.5 * double(1 << shift) * smallest;
  }
  if (inside && clampEdge_) {
    best.edgeZ = lastZ;
    best.edgeT = lastD;
  }
  return best;
}

double FarHorizons::pointTangent(const Point& p, double along, double z) const {
  double tangent = detail::kNoHorizon;
  const double t = p.along - along;
  // A sample at most half a cell ahead of the texel is none of its far field.
  if (p.t > 0.0 && t > 0.5 * smallestCell_) tangent = (p.z - z) / t - curvature_ * t;
  if (p.edgeT >= 0.0) {
    const double offset = p.t - t;
    const double edge = detail::clampedEdgeSlope(p.edgeZ - z, p.edgeT - offset, curvature_);
    if (edge > tangent) tangent = edge;
  }
  return tangent;
}

double FarHorizons::tangentAt(int col, int row, double z) const {
  return tangentAt(col, row, terrain_.x(col, row) * ux_ + terrain_.y(row) * uy_, z);
}

double FarHorizons::tangentAt(int col, int row, double along, double z) const {
  const int g = far_.options.spacing;
  const int dc = col - originCol_, dr = row - originRow_;
  const int i = latticeIndex(dc), j = latticeIndex(dr);
  const double wx = double(dc - i * g) / g, wy = double(dr - j * g) / g;
  const Point* p = &points_[static_cast<size_t>(j) * columns_ + i];
  const double t00 = pointTangent(p[0], along, z), t10 = pointTangent(p[1], along, z);
  const double t01 = pointTangent(p[columns_], along, z);
  const double t11 = pointTangent(p[columns_ + 1], along, z);
  const double most = std::max(std::max(t00, t10), std::max(t01, t11));
  const bool none = std::min(std::min(t00, t10), std::min(t01, t11)) <= detail::kNoHorizon;
  if (far_.options.maxOfCorners || none) return most;
  const double top = t00 + (t10 - t00) * wx, bottom = t01 + (t11 - t01) * wx;
  return top + (bottom - top) * wy;
}

void FarHorizons::mergeBlock(const HorizonBlock& b, float* merged) const {
  const TexelWindow& w = terrain_.window;
  // Window indices to field texels once per block; then a step along the
  // row (stride 1) or down the column.
  const int col = w.col + static_cast<int>(b.firstTexel % w.width);
  const int row = w.row + static_cast<int>(b.firstTexel / w.width);
  const bool alongRow = b.stride == 1;
  const int dCol = alongRow ? 1 : 0, dRow = 1 - dCol;
  const HeightView& heights = terrain_.heights;
  assert(!clampEdge_ && "the block sweep has open edges only");
  // The texels' heights and places along u, the places from the first
  // texel's: single precision is then good to well under a millimetre.
  // Whole vectors of 8 past the block, for the AVX2 path.
  constexpr int kRoom = HorizonBlock::kPaddedTexels + 8;
  alignas(32) float z[kRoom] = {}, along[kRoom] = {}, near[kRoom] = {}, out[kRoom];
  const double along0 = terrain_.x(col, row) * ux_ + terrain_.y(row) * uy_;
  for (int j = 0; j < b.count; ++j) {
    const int c = col + j * dCol, r = row + j * dRow;
    z[j] = heights.at(c, r);
    along[j] = static_cast<float>(terrain_.x(c, r) * ux_ + terrain_.y(r) * uy_ - along0);
    near[j] = b.tanHorizon[j];
  }
  // Runs of texels in one lattice cell (detail::FarCellRun).
  const int g = far_.options.spacing;
  detail::FarCellRun run;
  run.alongRow = alongRow;
  run.blend = !far_.options.maxOfCorners;
  run.halfCell = static_cast<float>(0.5 * smallestCell_);
  run.curvature = static_cast<float>(curvature_);
  run.wStep = 1.0f / g;
  const int firstOffset = alongRow ? col - originCol_ : row - originRow_;
  const int acrossOffset = alongRow ? row - originRow_ : col - originCol_;
  const int across = latticeIndex(acrossOffset);
  run.wAcross = float(acrossOffset - across * g) / g;
  [[maybe_unused]] const bool avx2 = detail::horizonAvx2();
  for (int j = 0; j < b.count;) {
    const int offset = firstOffset + j, cell = latticeIndex(offset);
    const int end = std::min(b.count, j + (cell + 1) * g - offset);
    const CellBound& c = bounds_[alongRow ? static_cast<size_t>(across) * (columns_ - 1) + cell
                                          : static_cast<size_t>(cell) * (columns_ - 1) + across];
    if (c.z <= detail::kNoHorizon) {  // no samples: the near horizons
      std::copy(near + j, near + end, out + j);
      j = end;
      continue;
    }
    run.top = static_cast<float>(c.z);
    run.invNear = static_cast<float>(c.invNear);
    run.invFar = static_cast<float>(c.invFar);
    for (int q = 0; q < 4; ++q) {
      run.along[q] = static_cast<float>(std::max(c.along[q] - along0, -1e30));
      run.height[q] = static_cast<float>(c.z4[q]);
    }
    run.wFirst = float(offset - cell * g) / g;
#if AAL_HORIZON_AVX2
    if (avx2) {
      detail::mergeFarRunAvx2(run, z + j, along + j, near + j, end - j, out + j);
      j = end;
      continue;
    }
#endif
    for (int k = j; k < end; ++k) {
      out[k] = detail::farMergedTangent(run, k - j, z[k], along[k], near[k]);
    }
    j = end;
  }
  std::copy(out, out + b.count, merged);
}

}  // namespace aal
