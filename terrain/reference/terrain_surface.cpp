#include "aperture/terrain/reference/terrain_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace aal {

namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The smallest t in [0, length] where q(t) = c0 + c1 t + c2 t^2 goes from
// q(0) >= 0 to below zero, or -1 when it stays at or above zero. q(0) >= 0
// up to rounding: the caller keeps the sign the ray started with.
double firstDescent(double c0, double c1, double c2, double length) {
  const double atEnd = c0 + length * (c1 + length * c2);
  // The roots in [0, length], in order.
  double roots[2];
  int count = 0;
  if (c2 == 0) {
    if (c1 != 0) roots[count++] = -c0 / c1;
  } else {
    const double discriminant = c1 * c1 - 4 * c2 * c0;
    if (discriminant >= 0) {
      const double q = -0.5 * (c1 + std::copysign(std::sqrt(discriminant), c1));
      double r0 = q / c2, r1 = q != 0 ? c0 / q : r0;
      if (r0 > r1) std::swap(r0, r1);
      roots[count++] = r0;
      roots[count++] = r1;
    }
  }
  if (atEnd < 0) {
    // An odd number of crossings: the first root in the segment (clamped,
    // for one that rounding put a hair outside it).
    for (int k = 0; k < count; ++k) {
      if (roots[k] >= -1e-9 * length && roots[k] <= length * (1 + 1e-9)) {
        return std::clamp(roots[k], 0.0, length);
      }
    }
    return count > 0 ? std::clamp(roots[0], 0.0, length) : 0.0;
  }
  // Both ends at or above zero: the ray can still dip under a bump between
  // two roots inside the segment.
  if (count == 2 && c2 > 0 && roots[0] > 0 && roots[1] < length && roots[0] < roots[1]) {
    return roots[0];
  }
  return -1;
}

}  // namespace

TerrainSurface::TerrainSurface(const Heightfield& field)
    : field_(field),
      cellX_(field.cellSizeXM),
      cellY_(field.cellSizeYM),
      halfX_(0.5 * (field.width - 1)),
      halfY_(0.5 * (field.height - 1)),
      maxHeight_(*std::max_element(field.z.begin(), field.z.end())) {}

bool TerrainSurface::inside(double x, double y) const {
  return std::abs(x) <= halfX_ * cellX_ + 1e-9 && std::abs(y) <= halfY_ * cellY_ + 1e-9;
}

double TerrainSurface::heightAt(double x, double y) const {
  return heightAtTexel(col(x), row(y));
}

glm::dvec3 TerrainSurface::normalAt(double x, double y) const {
  const double c = col(x), r = row(y);
  const double dx = heightAtTexel(c + 1, r) - heightAtTexel(c - 1, r);
  const double dy = heightAtTexel(c, r - 1) - heightAtTexel(c, r + 1);  // north is row - 1
  return glm::normalize(glm::dvec3(-dx / (2 * cellX_), -dy / (2 * cellY_), 1.0));
}

bool TerrainSurface::intersect(const glm::dvec3& origin, const glm::dvec3& dir, double sStart,
                               double sEnd, double& sHit) const {
  if (!(sEnd > sStart)) return false;
  const glm::dvec3 start = origin + sStart * dir;
  if (!inside(start.x, start.y)) return false;
  // Texel coordinates along the ray: u = col (east), v = row (south).
  const int width = field_.width, height = field_.height;
  const double uMax = width - 1, vMax = height - 1;
  const double u0 = col(origin.x), v0 = row(origin.y);
  const double du = dir.x / cellX_, dv = -dir.y / cellY_;
  const double uStart = std::clamp(u0 + sStart * du, 0.0, uMax);
  const double vStart = std::clamp(v0 + sStart * dv, 0.0, vMax);
  const int lastCol = std::max(width - 2, 0), lastRow = std::max(height - 2, 0);
  int i = std::min(static_cast<int>(uStart), lastCol);
  int j = std::min(static_cast<int>(vStart), lastRow);
  const int stepI = du > 0 ? 1 : -1, stepJ = dv > 0 ? 1 : -1;
  // The sign the ray starts with, +1 above the surface: a crossing makes
  // sign * (z - h) negative.
  const double sign = start.z < heightAt(start.x, start.y) ? -1.0 : 1.0;
  double s = sStart;
  while (s < sEnd) {
    const double z = origin.z + s * dir.z;
    if (dir.z >= 0 && z > maxHeight_) return false;
    // Where the ray leaves cell (i, j): its next column or row line (the
    // footprint's edge for a one-texel-wide DEM).
    const double uEdge = du > 0 ? std::min(i + 1.0, uMax) : double(i);
    const double vEdge = dv > 0 ? std::min(j + 1.0, vMax) : double(j);
    const double sU = du != 0 ? (uEdge - u0) / du : kInfinity;
    const double sV = dv != 0 ? (vEdge - v0) / dv : kInfinity;
    const double sNext = std::min({sU, sV, sEnd});
    const double length = sNext - s;
    if (length > 0) {
      // The patch h = h00 + hu a + hv b + k a b with a, b the position in
      // the cell, linear in t = s' - s along the ray.
      const int i1 = std::min(i + 1, width - 1), j1 = std::min(j + 1, height - 1);
      const double h00 = field_.at(i, j), h10 = field_.at(i1, j), h01 = field_.at(i, j1),
                   h11 = field_.at(i1, j1);
      const double hu = h10 - h00, hv = h01 - h00, k = h00 - h10 - h01 + h11;
      const double a = u0 + s * du - i, b = v0 + s * dv - j;
      const double c0 = z - (h00 + hu * a + hv * b + k * a * b);
      const double c1 = dir.z - (hu * du + hv * dv + k * (a * dv + b * du));
      const double c2 = -k * du * dv;
      const double t = firstDescent(sign * c0, sign * c1, sign * c2, length);
      if (t >= 0) {
        sHit = s + t;
        return true;
      }
    }
    if (sNext >= sEnd) return false;
    // Into the next cell; out of the footprint escapes.
    if (sU <= sNext) i += stepI;
    if (sV <= sNext) j += stepJ;
    if (i < 0 || i > lastCol || j < 0 || j > lastRow) return false;
    s = sNext;
  }
  return false;
}

bool TerrainSurface::clipToBox(const glm::dvec3& origin, const glm::dvec3& dir, double& sIn,
                               double& sOut) const {
  sIn = 0;
  sOut = 1e300;
  const double lo[3] = {-halfX_ * cellX_, -halfY_ * cellY_, -1e300};
  // The top a hair above the highest texel, so that a ray entering through
  // it starts above the surface (a flat DEM's surface is its top).
  const double hi[3] = {halfX_ * cellX_, halfY_ * cellY_, maxHeight_ + 1e-3 * cell()};
  for (int axis = 0; axis < 3; ++axis) {
    if (std::abs(dir[axis]) < 1e-300) {
      if (origin[axis] < lo[axis] || origin[axis] > hi[axis]) return false;
      continue;
    }
    double s0 = (lo[axis] - origin[axis]) / dir[axis], s1 = (hi[axis] - origin[axis]) / dir[axis];
    if (s0 > s1) std::swap(s0, s1);
    sIn = std::max(sIn, s0);
    sOut = std::min(sOut, s1);
  }
  // A hair inside, so that the first sample is within the footprint.
  const double inset = 1e-9 * (1 + sIn);
  sIn += inset;
  sOut -= inset;
  return sIn < sOut;
}

}  // namespace aal
