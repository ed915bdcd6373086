// Horizons of every texel for one azimuth in O(texels): a line sweep with a
// convex-hull stack (Stewart 1998; Timonen 2013). DESIGN §3 step 1.
//
// The grid is cut by straight lines parallel to the azimuth, one texel apart
// along the minor axis. Along the major axis a line advances one texel per
// step; its profile sample there is the terrain height linearly interpolated
// between the two texels it passes between (bilinear terrain along the line).
// Each line is walked from its far end in the +u direction back along -u,
// keeping the upper convex hull of the profile points (distance along u,
// height) already passed: the tangent from a sample to that hull is the
// sample's exact horizon over the whole line, and points that fall under the
// hull can never be a horizon again, so each is pushed and popped once.
// A texel lies between two neighbouring lines at its major coordinate: the
// tangent from the texel itself (its own position and height) to each line's
// hull is taken, and the two are weighted by the texel's distance to each
// line. Axis-aligned and diagonal lines pass through texel centres, where
// this is exact.
//
// Earth curvature drops a point at distance t by k t^2 (k = (1 - refraction)
// / 2R). With heights z~ = z - k t^2 (t measured along u from any origin) the
// true slope from p to q is slope~(p, q) + 2 k t_p, so the hull of z~ still
// gives the horizon.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "bake_terrain.h"

namespace aal {

struct HorizonSweepOptions {
  // Beyond the DEM edge the terrain continues at the edge height (else the
  // sky is open there).
  bool clampEdge = false;
  // Curvature drop coefficient k in drop = k t^2, in 1/metres; 0 = flat Earth.
  double curvature = 0.0;
  // Only terrain within this horizontal distance counts; 0 = no limit. With
  // a limit each texel scans its line up to that distance (O(distance)).
  double maxDistanceM = 0.0;
};

namespace detail {

struct ProfilePoint {
  double t;  // distance along u, metres
  double z;  // height with the curvature drop applied (z~)
};

struct SweepLayout {
  bool majorIsColumn = true;
  int majorLength = 0, minorLength = 0;
  int start = 0, step = 1;       // major index of sweep step k: start + k * step
  double minorPerStep = 0;       // line c lies at minor coordinate c + k * minorPerStep
  std::vector<int> floorOffset;  // floor(k * minorPerStep)
  std::vector<double> fraction;  // k * minorPerStep - floorOffset[k]
  int firstLine = 0, lastLine = 0;
};

inline SweepLayout makeSweepLayout(const BakeTerrain& terrain, double ux, double uy) {
  SweepLayout s;
  // Direction of +u in grid units (columns east, rows south) at the centre row.
  const double dc = ux / terrain.rowCellX[terrain.height / 2];
  const double dr = -uy / terrain.cellY;
  s.majorIsColumn = std::abs(dc) >= std::abs(dr);
  s.majorLength = s.majorIsColumn ? terrain.width : terrain.height;
  s.minorLength = s.majorIsColumn ? terrain.height : terrain.width;
  const double dMajor = s.majorIsColumn ? dc : dr, dMinor = s.majorIsColumn ? dr : dc;
  // Start at the +u end and move along -u.
  s.start = dMajor > 0 ? s.majorLength - 1 : 0;
  s.step = dMajor > 0 ? -1 : 1;
  s.minorPerStep = -dMinor / std::abs(dMajor);
  // Snap directions within rounding of an axis or diagonal onto it, so that
  // their lines pass exactly through texel centres.
  for (double exact : {-1.0, 0.0, 1.0}) {
    if (std::abs(s.minorPerStep - exact) < 1e-12) s.minorPerStep = exact;
  }
  s.floorOffset.resize(s.majorLength);
  s.fraction.resize(s.majorLength);
  int lo = 0, hi = 0;
  for (int k = 0; k < s.majorLength; ++k) {
    const double offset = k * s.minorPerStep;
    s.floorOffset[k] = static_cast<int>(std::floor(offset));
    s.fraction[k] = offset - s.floorOffset[k];
    lo = std::min(lo, s.floorOffset[k]);
    hi = std::max(hi, s.floorOffset[k]);
  }
  // Texel (k, j) lies between lines j - floorOffset[k] - 1 and j - floorOffset[k].
  s.firstLine = -hi - 1;
  s.lastLine = s.minorLength - 1 - lo;
  return s;
}

// Largest slope from p to the terrain that continues flat at the edge height
// beyond the edge point (distance `toEdge` ahead, height difference
// `rise`), counting only the part beyond the edge: its nearest point is the
// edge point itself, which the hull already holds.
inline double clampedEdgeSlope(double rise, double toEdge, double curvature) {
  if (toEdge <= 0.0) return 0.0;  // p is the edge point: flat ground at its own height
  if (rise >= 0.0) return -std::numeric_limits<double>::infinity();
  if (curvature <= 0.0) return 0.0;  // approaches the horizontal at infinity
  const double tangentDistance = std::sqrt(-rise / curvature);
  if (tangentDistance <= toEdge) return -std::numeric_limits<double>::infinity();
  return -2.0 * std::sqrt(-rise * curvature);
}

// Slope from q to the upper hull's tangent point (the hull holds points all
// ahead of q, farthest first). Seen from a point behind the chain, the slope
// to its vertices rises up to the tangent point and falls after it, so a
// binary search finds it.
inline double hullTangentSlope(const std::vector<ProfilePoint>& hull, const ProfilePoint& q) {
  auto atLeastAsSteep = [&](size_t far, size_t near) {  // slope(q, far) >= slope(q, near)
    return (hull[far].z - q.z) * (hull[near].t - q.t) >= (hull[near].z - q.z) * (hull[far].t - q.t);
  };
  // Largest i with !atLeastAsSteep(i - 1, i) is the tangent point (0 if none).
  size_t lo = 0, hi = hull.size() - 1;
  while (lo < hi) {
    const size_t mid = (lo + hi + 1) / 2;
    if (atLeastAsSteep(mid - 1, mid)) {
      hi = mid - 1;
    } else {
      lo = mid;
    }
  }
  return (hull[lo].z - q.z) / (hull[lo].t - q.t);
}

// Horizon tangents along one line for the texels on both sides of it, as
// seen from each texel's own position: nearSide[k] for the texel at or just
// past the line (minor index line + floorOffset[k]), farSide[k] for the one
// after it (+1), NaN where that texel or the line is outside the grid.
inline void sweepLine(const BakeTerrain& terrain, const SweepLayout& layout, int line, double ux,
                      double uy, const HorizonSweepOptions& options,
                      std::vector<ProfilePoint>& hull, std::vector<double>& nearSide,
                      std::vector<double>& farSide) {
  const Heightfield& field = *terrain.field;
  const double k = options.curvature, maxDistance = options.maxDistanceM;
  constexpr double kNone = -std::numeric_limits<double>::infinity();
  constexpr double kOutside = std::numeric_limits<double>::quiet_NaN();
  const int minorMax = layout.minorLength - 1;
  hull.clear();
  bool started = false;
  double edgeT = 0, edgeZ = 0;

  // Metric position of the grid point (major, minor) projected on u.
  auto along = [&](int major, double minor) {
    if (layout.majorIsColumn) {
      const int nearRow = std::clamp(static_cast<int>(std::lround(minor)), 0, minorMax);
      return (major - terrain.centreCol) * terrain.rowCellX[nearRow] * ux +
             (0.5 * (terrain.height - 1) - minor) * terrain.cellY * uy;
    }
    return (minor - terrain.centreCol) * terrain.rowCellX[major] * ux + terrain.y(major) * uy;
  };
  auto heightAt = [&](int major, int minor) {
    return layout.majorIsColumn ? field.at(major, minor) : field.at(minor, major);
  };
  // Slope of the bilinear surface leaving texel (col, row) in direction u:
  // the cell it enters rises along x and y by the one-sided differences. The
  // line samples are a cell apart, so without this a texel in a crease would
  // miss the wall right next to it (and see more sky than the terrain allows).
  const int dCol = ux > 0 ? 1 : -1, dRow = uy > 0 ? -1 : 1;  // rows grow south
  const double wx = std::abs(ux) > 1e-12 ? std::abs(ux) : 0.0;
  const double wy = std::abs(uy) > 1e-12 ? std::abs(uy) : 0.0;
  auto leavingSlope = [&](int col, int row, double z) {
    const int c = col + dCol, r = row + dRow;
    double slope = 0.0;
    if (wx > 0.0) {
      if (c < 0 || c >= field.width) return kNone;  // the cell ahead is off the grid
      slope += wx * (field.at(c, row) - z) / terrain.rowCellX[row];
    }
    if (wy > 0.0) {
      if (r < 0 || r >= field.height) return kNone;
      slope += wy * (field.at(col, r) - z) / terrain.cellY;
    }
    return slope;
  };
  // Horizon of profile point q (true height z) over the line's points passed so far.
  auto horizonOf = [&](const ProfilePoint& q, double z) {
    double best = kNone;
    if (maxDistance > 0.0) {
      // Exact within the distance limit: scan the line's nearer points.
      for (size_t i = hull.size(); i-- > 0 && hull[i].t - q.t <= maxDistance;) {
        best = std::max(best, (hull[i].z - q.z) / (hull[i].t - q.t));
      }
    } else if (!hull.empty()) {
      best = hullTangentSlope(hull, q);
    }
    if (best != kNone) best += 2.0 * k * q.t;
    if (started && options.clampEdge && (maxDistance <= 0.0 || edgeT - q.t <= maxDistance)) {
      best = std::max(best, clampedEdgeSlope(edgeZ - z, edgeT - q.t, k));
    }
    return best;
  };
  auto withLeavingSlope = [&](double horizon, int major, int minor) {
    const int col = layout.majorIsColumn ? major : minor,
              row = layout.majorIsColumn ? minor : major;
    return std::max(horizon, leavingSlope(col, row, heightAt(major, minor)));
  };

  for (int step = 0; step < layout.majorLength; ++step) {
    const int major = layout.start + step * layout.step;
    const double minor = line + step * layout.minorPerStep;
    const int texel = line + layout.floorOffset[step];
    const double w = layout.fraction[step];
    const bool onGrid = minor >= 0.0 && minor <= minorMax;
    if (!onGrid) {
      nearSide[step] = farSide[step] = kOutside;
      continue;
    }
    // The line's sample: linear between the two texels it passes between.
    const int j0 = texel, j1 = std::min(texel + 1, minorMax);
    const double z = (1 - w) * heightAt(major, j0) + w * heightAt(major, j1);
    const double t = along(major, minor);
    const ProfilePoint p{t, z - k * t * t};
    if (!started) {
      started = true;
      edgeT = t;
      edgeZ = z;
    }
    // Horizon of the sample (before it joins the hull), for the texels on
    // both sides; each adds its own leaving slope.
    const double sampleHorizon = horizonOf(p, z);
    nearSide[step] = withLeavingSlope(sampleHorizon, major, texel);
    farSide[step] = w > 0.0 && texel + 1 <= minorMax
                        ? withLeavingSlope(sampleHorizon, major, texel + 1)
                        : kOutside;
    if (maxDistance > 0.0) {
      hull.push_back(p);
      continue;
    }
    // Pop points on or under the segment from p to the one behind them: they
    // are off the upper hull from now on.
    while (hull.size() >= 2) {
      const ProfilePoint& a = hull[hull.size() - 1];
      const ProfilePoint& b = hull[hull.size() - 2];
      if ((b.z - p.z) * (a.t - p.t) >= (a.z - p.z) * (b.t - p.t)) {
        hull.pop_back();
      } else {
        break;
      }
    }
    hull.push_back(p);
  }
}

// Tangent at a texel between two lines, weighted by distance; a line with
// nothing ahead (-inf) or outside the grid (NaN) leaves the other one (at
// the grid's edges a texel may have only one line beside it).
inline double blendHorizons(double near, double far, double farWeight) {
  const bool haveFar = farWeight > 0.0 && !std::isnan(far) && !std::isinf(far);
  const bool haveNear = !std::isnan(near) && !std::isinf(near);
  if (haveNear && haveFar) return near + farWeight * (far - near);
  if (haveNear) return near;
  if (haveFar) return far;
  return -std::numeric_limits<double>::infinity();
}

}  // namespace detail

// Calls visit(texelIndex, tanHorizon) once for every texel for the azimuth
// phi (radians, counter-clockwise from east; u = (cos phi, sin phi) in the
// world frame). tanHorizon is the tangent of the horizon elevation, -inf when
// no terrain lies ahead. Lines run in parallel: visit is called concurrently,
// but never twice for the same texel.
template <class Visit>
void sweepHorizons(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& options,
                   Visit&& visit) {
  const double ux = std::cos(phi), uy = std::sin(phi);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy);
  const Heightfield& field = *terrain.field;

  struct Scratch {
    std::vector<detail::ProfilePoint> hull;
    std::vector<double> near, far, previousFar;
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  // Texel (k, line + floorOffset[k]) lies between lines c - 1 and c; it
  // takes line c's horizon with weight 1 - fraction[k] and line c - 1's with
  // fraction[k]. So each block of lines also sweeps the line just before it.
  tbb::parallel_for(
      tbb::blocked_range<int>(layout.firstLine + 1, layout.lastLine + 1, 16),
      [&](const tbb::blocked_range<int>& lines) {
        Scratch& s = scratch.local();
        s.near.resize(layout.majorLength);
        s.far.resize(layout.majorLength);
        s.previousFar.resize(layout.majorLength);
        detail::sweepLine(terrain, layout, lines.begin() - 1, ux, uy, options, s.hull, s.near,
                          s.previousFar);
        for (int line = lines.begin(); line != lines.end(); ++line) {
          detail::sweepLine(terrain, layout, line, ux, uy, options, s.hull, s.near, s.far);
          for (int step = 0; step < layout.majorLength; ++step) {
            const int minor = line + layout.floorOffset[step];
            if (minor < 0 || minor >= layout.minorLength) continue;
            const int major = layout.start + step * layout.step;
            const size_t index =
                layout.majorIsColumn ? field.index(major, minor) : field.index(minor, major);
            visit(index,
                  detail::blendHorizons(s.near[step], s.previousFar[step], layout.fraction[step]));
          }
          std::swap(s.previousFar, s.far);
        }
      });
}

}  // namespace aal
