#include "aperture/preprocess/far_horizon.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>

#include <tbb/parallel_for.h>

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
      points_[static_cast<size_t>(j) * columns_ + i] =
          march(terrain, originCol_ + i * g, originRow_ + j * g);
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

double FarHorizons::pointTangent(const Point& p, double x, double y, double z) const {
  const double offset = (x - p.x) * ux_ + (y - p.y) * uy_;
  double tangent = detail::kNoHorizon;
  const double t = p.t - offset;
  // A sample at most half a cell ahead of the texel is none of its far field.
  if (p.t > 0.0 && t > 0.5 * smallestCell_) tangent = (p.z - z) / t - curvature_ * t;
  if (p.edgeT >= 0.0) {
    const double edge = detail::clampedEdgeSlope(p.edgeZ - z, p.edgeT - offset, curvature_);
    if (edge > tangent) tangent = edge;
  }
  return tangent;
}

double FarHorizons::tangentAt(int col, int row, double z) const {
  const int g = far_.options.spacing;
  const int dc = col - originCol_, dr = row - originRow_;
  const int i = latticeIndex(dc), j = latticeIndex(dr);
  const double wx = double(dc - i * g) / g, wy = double(dr - j * g) / g;
  const Point* p = &points_[static_cast<size_t>(j) * columns_ + i];
  const double x = terrain_.x(col, row), y = terrain_.y(row);
  const double t00 = pointTangent(p[0], x, y, z), t10 = pointTangent(p[1], x, y, z);
  const double t01 = pointTangent(p[columns_], x, y, z);
  const double t11 = pointTangent(p[columns_ + 1], x, y, z);
  const double most = std::max(std::max(t00, t10), std::max(t01, t11));
  const bool none = std::min(std::min(t00, t10), std::min(t01, t11)) <= detail::kNoHorizon;
  if (far_.options.maxOfCorners || none) return most;
  const double top = t00 + (t10 - t00) * wx, bottom = t01 + (t11 - t01) * wx;
  return top + (bottom - top) * wy;
}

}  // namespace aal
