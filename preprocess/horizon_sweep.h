// Horizons of every texel for one azimuth in O(texels): a line sweep with a
// convex-hull stack (Stewart 1998; Timonen 2013). docs/design.md §3 step 1.
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
// A bake window (BakeTerrain::window, a tile of the field) keeps the whole
// field's lines, positions and heights: only the texels inside it are
// visited, and only the steps that reach them are walked. With a distance
// limit a line starts a little more than that distance before the window
// (the points farther away cannot count), so a tile's horizons equal the
// whole field's bit for bit; without one, lines start at the field's edge.
//
// Earth curvature drops a point at distance t by k t^2 (k = (1 - refraction)
// / 2R). With heights z~ = z - k t^2 (t measured along u from any origin) the
// true slope from p to q is slope~(p, q) + 2 k t_p, so the hull of z~ still
// gives the horizon.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "aperture/preprocess/bake_terrain.h"

namespace aal {

struct HorizonSweepOptions {
  // Beyond the DEM edge the terrain continues at the edge height (else the
  // sky is open there).
  bool clampEdge = false;
  // Curvature drop coefficient k in drop = k t^2, in 1/metres; 0 = flat Earth.
  double curvature = 0.0;
  // Only terrain within this horizontal distance counts; 0 = no limit.
  // Short limits are scanned point by point (scansWithinLimit, and
  // LineWalker up to its own kScanWithinSteps), longer ones taken from
  // LineWalker's chunks' hulls.
  double maxDistanceM = 0.0;
  // Without a distance limit: a partial window's lines start this far
  // before it (0: at the field's edge), so each texel's horizon covers at
  // least this distance of its line (the far field, far_horizon.h, adds
  // what lies beyond).
  double windowReachM = 0.0;
};

// Texels side by side along the minor axis of a sweep: texel j (0 <= j <
// count) is at (major, minorFirst + j) as (column, row) where majorIsColumn,
// else (minorFirst + j, major), with horizon tangent tanHorizon[j] (-inf
// when no terrain lies ahead).
struct HorizonRun {
  // The lines a sweep walks together, so the most texels in a run: 32
  // walked a 1024² fBm with a limit 8-9 % faster than 16 (300 m and 3 km,
  // the sums taking a run as a block), 39 the same as 32.
  static constexpr int kMaxCount = 32;
  bool majorIsColumn;
  int major;
  int minorFirst;
  int count;
  const double* tanHorizon;
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
  // Steps [firstStep, endStep) are walked; texels are visited from
  // visitStep on (the steps before only fill the hulls), those with minor
  // coordinates in [minorBegin, minorEnd): the window's.
  int firstStep = 0, visitStep = 0, endStep = 0;
  int minorBegin = 0, minorEnd = 0;
  // A partial window's lines with a reach: where each line, firstLine ..
  // lastLine, starts, the reach before the first step at which it passes
  // beside a window texel (never before firstStep). A line that passes
  // beside the window's side starts there, not the reach before the
  // window's first step: oblique passes of a tile walked up to twice the
  // steps they visit. Empty: every line starts at firstStep.
  std::vector<int> lineStart;
  int startOf(int line) const {
    const size_t i = static_cast<size_t>(line - firstLine);
    return line >= firstLine && i < lineStart.size() ? lineStart[i] : firstStep;
  }
};

// Sweep steps that cover `distance` metres along any line: a step advances
// at least one cell (the smallest of the field) along u. The margin holds
// the small unevenness of t along a line on geographic grids.
inline int stepsCovering(const BakeTerrain& terrain, double distance) {
  double smallest = terrain.cellY;
  for (double cellX : terrain.rowCellX) smallest = std::min(smallest, cellX);
  return static_cast<int>(std::min(std::ceil(distance / smallest), 1e9)) + 4;
}

// A limit that stepsCovering gives this many steps or fewer is scanned by
// the block sweeps (horizon_blocks.h), 8 lines at a time: cheaper than
// LineWalker's chunks up to about here (a 1024² fBm of 30 m cells, --svf,
// 32 azimuths, CPU time: 1.70-1.75 against 2.12-2.17 s at 14 km, 471
// steps; the scan grows by about 3 ms a step, the chunks stay at 2.1-2.2
// s; docs/performance.md). Below ScanRing::kSteps.
inline constexpr int kBlockScanSteps = 500;
// The same where rows' cells differ (geographic grids), whose scan divides
// (about 8.5 ms a step).
inline constexpr int kBlockScanStepsUneven = 200;

// Whether the block sweeps take options' distance limit, which they scan
// point by point (a limit that is set and short: kBlockScanSteps).
inline bool scansWithinLimit(const BakeTerrain& terrain, const HorizonSweepOptions& options) {
  return options.maxDistanceM > 0.0 &&
         stepsCovering(terrain, options.maxDistanceM) <=
             (terrain.uniformCellX ? kBlockScanSteps : kBlockScanStepsUneven);
}

// How far before a window (or a whole field, with a distance limit) a
// sweep's lines start: the limit, else the window's reach (0: at the
// field's edge).
inline double sweepReachM(const HorizonSweepOptions& options) {
  return options.maxDistanceM > 0.0 ? options.maxDistanceM : options.windowReachM;
}

// `maxDistanceM` (0 = none) sets how far before a partial window lines start.
inline SweepLayout makeSweepLayout(const BakeTerrain& terrain, double ux, double uy,
                                   double maxDistanceM = 0.0) {
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
  for (int k = 0; k < s.majorLength; ++k) {
    const double offset = k * s.minorPerStep;
    s.floorOffset[k] = static_cast<int>(std::floor(offset));
    s.fraction[k] = offset - s.floorOffset[k];
  }
  // The window's major range in steps (major = start + k * step).
  const TexelWindow& w = terrain.window;
  const int majorBegin = s.majorIsColumn ? w.col : w.row;
  const int majorEnd = majorBegin + (s.majorIsColumn ? w.width : w.height);
  s.minorBegin = s.majorIsColumn ? w.row : w.col;
  s.minorEnd = s.minorBegin + (s.majorIsColumn ? w.height : w.width);
  s.visitStep = s.step < 0 ? s.majorLength - majorEnd : majorBegin;
  s.endStep = s.step < 0 ? s.majorLength - majorBegin : majorEnd;
  const int reach = maxDistanceM > 0.0 ? stepsCovering(terrain, maxDistanceM) : 0;
  s.firstStep = maxDistanceM > 0.0 ? std::max(0, s.visitStep - reach) : 0;
  int lo = s.floorOffset[s.visitStep], hi = lo;
  for (int k = s.visitStep; k < s.endStep; ++k) {
    lo = std::min(lo, s.floorOffset[k]);
    hi = std::max(hi, s.floorOffset[k]);
  }
  // Texel (k, j) lies between lines j - floorOffset[k] - 1 and j - floorOffset[k].
  s.firstLine = s.minorBegin - hi - 1;
  s.lastLine = s.minorEnd - 1 - lo;
  if (maxDistanceM > 0.0) {
    // The lines beside the window's texels at step k are minorBegin - 1 -
    // floorOffset[k] .. minorEnd - 1 - floorOffset[k]: a run that moves by
    // at most one line a step, so those met so far are one run too.
    s.lineStart.assign(static_cast<size_t>(s.lastLine - s.firstLine + 1), s.endStep);
    const auto meet = [&](int from, int to, int k) {  // lines from .. to, first met at step k
      for (int line = from; line <= to; ++line) {
        s.lineStart[static_cast<size_t>(line - s.firstLine)] = std::max(s.firstStep, k - reach);
      }
    };
    int metLo = s.minorBegin - 1 - s.floorOffset[s.visitStep], metHi = metLo - 1;  // none yet
    for (int k = s.visitStep; k < s.endStep; ++k) {
      const int a = s.minorBegin - 1 - s.floorOffset[k], b = s.minorEnd - 1 - s.floorOffset[k];
      meet(a, std::min(b, metLo - 1), k);
      meet(std::max(a, metHi + 1), b, k);
      metLo = std::min(metLo, a);
      metHi = std::max(metHi, b);
    }
  }
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

// "No horizon": nothing ahead on the line (or the line is off the grid).
// A finite sentinel keeps the inner loops free of NaN/inf tests.
constexpr double kNoHorizon = -1e300;

// Metric position of a sweep's grid point (major, minor) projected on
// u = (ux, uy): a line's place along u, which its hull points are placed by
// (LineWalker, BlockLineWalker). Columns' x from the row nearest `minor`.
template <bool kMajorIsColumn>
inline double placeAlongU(const BakeTerrain& terrain, int major, double minor, double ux,
                          double uy) {
  if constexpr (kMajorIsColumn) {
    const int nearRow = std::min(static_cast<int>(minor + 0.5), terrain.height - 1);
    return (major - terrain.centreCol) * terrain.rowCellX[nearRow] * ux +
           (0.5 * (terrain.height - 1) - minor) * terrain.cellY * uy;
  } else {
    return (minor - terrain.centreCol) * terrain.rowCellX[major] * ux + terrain.y(major) * uy;
  }
}

// Walks the lines of one azimuth. Lines are stepped in lockstep in groups of
// neighbours so that the texels touched at one step sit together in memory
// whatever the azimuth. kMajorIsColumn: lines advance column by column.
template <bool kMajorIsColumn>
class LineWalker {
 public:
  // What a distance-limited walk undoes of a push onto Line::before: the
  // hull after push k ends at pushes[k].at, so it holds pushes[k].at + 1
  // points.
  struct Push {
    size_t at;                 // where the point went
    ProfilePoint overwritten;  // what lay there
  };
  struct Line {
    // Storage; the upper hull is hull[0 .. size), farthest point first.
    // With a distance limit every point walked, in order.
    std::vector<ProfilePoint> hull;
    size_t size = 0;
    bool started = false;
    double edgeT = 0, edgeZ = 0;  // the line's first point: the DEM edge ahead
    bool edgeIsField = true;      // false: the walk began inside the field (windowReachM)
    // With a distance limit, the points within it of the newest one are
    // those of its chunk, the points walked since the last cut (all within
    // the limit), and the nearer part of the chunk before it, whose upper
    // hull is kept nearest first for each part as the part shrinks
    // (LineWalker::pushWithin).
    size_t chunkFirst = 0;            // hull[] index of the chunk's first point
    std::vector<ProfilePoint> chunk;  // the chunk's upper hull, farthest first
    size_t chunkSize = 0;
    std::vector<ProfilePoint> before;  // the chunk before: the hull of its part, nearest first
    size_t beforeEnd = 0;              // hull[] index after that chunk's last point
    std::vector<Push> pushes;          // the pushes that built `before`, nearest point first
    size_t pushCount = 0;              // of which the first pushCount stand: the part's points
  };

  LineWalker(const BakeTerrain& terrain, const SweepLayout& layout, double ux, double uy,
             const HorizonSweepOptions& options)
      : terrain_(terrain),
        heights_(terrain.heights),
        layout_(layout),
        ux_(ux),
        uy_(uy),
        curvature_(options.curvature),
        maxDistance_(options.maxDistanceM),
        clampEdge_(options.clampEdge),
        minorMax_(layout.minorLength - 1),
        dCol_(ux > 0 ? 1 : -1),
        dRow_(uy > 0 ? -1 : 1),  // rows grow south
        wx_(std::abs(ux) > 1e-12 ? std::abs(ux) : 0.0),
        wy_(std::abs(uy) > 1e-12 ? std::abs(uy) : 0.0),
        invCellY_(1.0 / terrain.cellY),
        scanWithin_(options.maxDistanceM > 0.0 &&
                    stepsCovering(terrain, options.maxDistanceM) <= kScanWithinSteps) {}

  void reset(Line& line) const {
    line.hull.resize(static_cast<size_t>(layout_.majorLength));
    line.size = 0;
    line.started = false;
    line.chunkFirst = line.chunkSize = line.beforeEnd = line.pushCount = 0;
  }

  // Advances `line` (state `state`) by sweep step `step` and returns the
  // horizon tangent of its sample there, kNoHorizon when nothing lies ahead
  // or the line is off the grid at that step (or `horizon` is false: the
  // step only fills the hull).
  [[gnu::always_inline]] double step(Line& state, int line, int step, bool horizon = true) const {
    const double minor = line + step * layout_.minorPerStep;
    if (minor < 0.0 || minor > minorMax_) return kNoHorizon;
    const int major = layout_.start + step * layout_.step;
    const int texel = line + layout_.floorOffset[step];
    const double w = layout_.fraction[step];
    // The line's sample: linear between the two texels it passes between.
    const double z =
        (1 - w) * heightAt(major, texel) + w * heightAt(major, std::min(texel + 1, minorMax_));
    const double t = along(major, minor);
    const ProfilePoint p{t, z - curvature_ * t * t};
    if (!state.started) {
      state.started = true;
      state.edgeT = t;
      state.edgeZ = z;
      const double before = line + (step - 1) * layout_.minorPerStep;
      state.edgeIsField = step == 0 || before < 0.0 || before > minorMax_;
    }
    if (maxDistance_ <= 0.0) {
      state.size = pushOnHull(state.hull.data(), state.size, p);
    } else {
      state.hull[state.size++] = p;
      if (!scanWithin_) pushWithin(state, p);
    }
    return horizon ? horizonOfNewest(state, z) : kNoHorizon;
  }

  // Slope of the bilinear surface leaving texel (col, row) along u: the cell
  // it enters rises along x and y by the one-sided differences. The line
  // samples are a cell apart, so without this a texel in a crease would miss
  // the wall right next to it (and see more sky than the terrain allows).
  [[gnu::always_inline]] double leavingSlope(int col, int row) const {
    const double z = heights_.at(col, row);
    double slope = 0.0;
    if (wx_ > 0.0) {
      const int c = col + dCol_;
      if (c < 0 || c >= terrain_.width) return kNoHorizon;  // the cell ahead is off the grid
      slope += wx_ * (heights_.at(c, row) - z) * terrain_.rowInvCellX[row];
    }
    if (wy_ > 0.0) {
      const int r = row + dRow_;
      if (r < 0 || r >= terrain_.height) return kNoHorizon;
      slope += wy_ * (heights_.at(col, r) - z) * invCellY_;
    }
    return slope;
  }

 private:
  float heightAt(int major, int minor) const {
    return kMajorIsColumn ? heights_.at(major, minor) : heights_.at(minor, major);
  }

  // Metric position of the grid point (major, minor) projected on u.
  double along(int major, double minor) const {
    return placeAlongU<kMajorIsColumn>(terrain_, major, minor, ux_, uy_);
  }

  // Pushes p onto the upper hull hull[0 .. n), farthest point first, and
  // returns its new size: points on or under the segment from p to the one
  // behind them are off the hull from now on. The tangent from p to the
  // hull is then the point right behind it.
  static size_t pushOnHull(ProfilePoint* hull, size_t n, const ProfilePoint& p) {
    while (n >= 2 && (hull[n - 2].z - p.z) * (hull[n - 1].t - p.t) >=
                         (hull[n - 1].z - p.z) * (hull[n - 2].t - p.t)) {
      --n;
    }
    hull[n] = p;
    return n + 1;
  }

  // With a distance limit: p, the line's newest point, joins its chunk's
  // hull; where the chunk's first point lies beyond the limit from p, p
  // starts a new chunk, and the old one becomes the chunk before, its upper
  // hull built from its nearest point on with each push recorded, so that
  // horizonWithin can take its farthest points off again one by one. The
  // horizon within the limit is then the higher of two tangents: O(1) and
  // O(log n) per point instead of a scan of every point within the limit
  // (docs/baking.md, "The sweep").
  void pushWithin(Line& s, const ProfilePoint& p) const {
    const size_t newest = s.size - 1;
    if (s.chunkSize > 0 && s.hull[s.chunkFirst].t - p.t > maxDistance_) {
      buildBefore(s, s.chunkFirst, newest);
      s.chunkFirst = newest;
      s.chunkSize = 0;
    }
    if (s.chunk.size() <= s.chunkSize) s.chunk.resize(2 * s.chunkSize + 2);
    s.chunkSize = pushOnHull(s.chunk.data(), s.chunkSize, p);
  }

  // The upper hull of hull[first .. end), nearest (last walked) point
  // first, into s.before, each push recorded in s.pushes.
  static void buildBefore(Line& s, size_t first, size_t end) {
    const size_t points = end - first;
    if (s.before.size() < points + 1) s.before.resize(2 * points + 2);
    if (s.pushes.size() < points) s.pushes.resize(2 * points);
    ProfilePoint* b = s.before.data();
    size_t n = 0, k = 0;
    for (size_t i = end; i-- > first;) {
      const ProfilePoint& c = s.hull[i];
      // t grows along b: pop the last point where it lies on or under the
      // segment from the one before it to c.
      while (n >= 2 && (b[n - 1].t - b[n - 2].t) * (c.z - b[n - 2].z) >=
                           (b[n - 1].z - b[n - 2].z) * (c.t - b[n - 2].t)) {
        --n;
      }
      s.pushes[k++] = Push{n, b[n]};
      b[n++] = c;
    }
    s.beforeEnd = end;
    s.pushCount = k;
  }

  // The highest slope from q, the line's newest point, to the points within
  // the limit: the point behind it on its chunk's hull, and the tangent
  // from q to the hull of the chunk before, whose points beyond the limit
  // are taken off first (the farthest was pushed last).
  double horizonWithin(Line& s, const ProfilePoint& q) const {
    double best = kNoHorizon;
    if (s.chunkSize >= 2) {
      const ProfilePoint& a = s.chunk[s.chunkSize - 2];
      best = (a.z - q.z) / (a.t - q.t);
    }
    while (s.pushCount > 0 && s.hull[s.beforeEnd - s.pushCount].t - q.t > maxDistance_) {
      const Push& undo = s.pushes[--s.pushCount];
      s.before[undo.at] = undo.overwritten;
    }
    if (s.pushCount == 0) return best;
    // The slopes from q along the hull rise to the tangent and then fall:
    // find the first point the next one does not rise above.
    const ProfilePoint* b = s.before.data();
    size_t lo = 0, hi = s.pushes[s.pushCount - 1].at;
    while (lo < hi) {
      const size_t mid = (lo + hi) / 2;
      if ((b[mid + 1].z - q.z) * (b[mid].t - q.t) > (b[mid].z - q.z) * (b[mid + 1].t - q.t)) {
        lo = mid + 1;
      } else {
        hi = mid;
      }
    }
    return std::max(best, (b[lo].z - q.z) / (b[lo].t - q.t));
  }

  // Horizon of the point just pushed (true height z): with a distance limit,
  // a scan of the points within it where it is short, else horizonWithin;
  // without one the tangent to the hull, which is the point right behind
  // it. Always inlined: GCC stopped
  // inlining it into bake.cpp's sweeps once the block sweep moved out of
  // that file (a smaller unit, less room to grow), 5 % more instructions.
  [[gnu::always_inline]] double horizonOfNewest(Line& state, double z) const {
    const ProfilePoint* hull = state.hull.data();
    const size_t n = state.size;
    const ProfilePoint& q = hull[n - 1];
    double best = kNoHorizon;
    if (scanWithin_) {
      for (size_t i = n - 1; i-- > 0 && hull[i].t - q.t <= maxDistance_;) {
        best = std::max(best, (hull[i].z - q.z) / (hull[i].t - q.t));
      }
    } else if (maxDistance_ > 0.0) {
      best = horizonWithin(state, q);
    } else if (n >= 2) {
      best = (hull[n - 2].z - q.z) / (hull[n - 2].t - q.t);
    }
    if (best != kNoHorizon) best += 2.0 * curvature_ * q.t;
    if (clampEdge_ &&
        (maxDistance_ <= 0.0 ? state.edgeIsField : state.edgeT - q.t <= maxDistance_)) {
      const double edge = clampedEdgeSlope(state.edgeZ - z, state.edgeT - q.t, curvature_);
      if (edge > best) best = edge;
    }
    return best;
  }

  const BakeTerrain& terrain_;
  const HeightView heights_;  // the walker's own copy: one load fewer per height
  const SweepLayout& layout_;
  const double ux_, uy_, curvature_, maxDistance_;
  const bool clampEdge_;
  const int minorMax_, dCol_, dRow_;
  const double wx_, wy_, invCellY_;
  // A limit that stepsCovering gives this many steps or fewer is scanned
  // point by point: cheaper than the chunks' hulls up to about 1 km on a
  // 1024² fBm of 30 m cells (the bake alone, 32 azimuths: 0.84 against
  // 1.13 s at 150 m, 1.22 against 1.40 at 900 m, 1.44 against 1.33 at
  // 1.2 km, 2.39 against 1.33 at 3 km; docs/performance.md).
  static constexpr int kScanWithinSteps = 40;
  const bool scanWithin_;
};

// Tangent at a texel between two lines, weighted by distance; a line with
// nothing ahead or off the grid (kNoHorizon) leaves the other one (at the
// grid's edges a texel may have only one line beside it).
inline double blendHorizons(double near, double far, double farWeight) {
  if (far <= kNoHorizon || farWeight == 0.0) return near;
  if (near <= kNoHorizon) return far;
  return near + farWeight * (far - near);
}

template <bool kMajorIsColumn, class VisitRun>
void sweepLines(const BakeTerrain& terrain, const SweepLayout& layout, double ux, double uy,
                const HorizonSweepOptions& options, VisitRun& visitRun) {
  const LineWalker<kMajorIsColumn> walker(terrain, layout, ux, uy, options);
  constexpr int kGroup = HorizonRun::kMaxCount;
  struct Scratch {
    std::vector<typename LineWalker<kMajorIsColumn>::Line> lines{kGroup + 1};
    double horizon[kGroup + 1];
    double run[kGroup];
  };
  tbb::enumerable_thread_specific<Scratch> scratch;
  // Texel (k, line + floorOffset[k]) lies between lines c - 1 and c: it
  // takes line c's horizon with weight 1 - fraction[k] and line c - 1's with
  // fraction[k], and at least the slope of the surface leaving it. So each
  // group of lines also walks the line just before it.
  const int firstLine = layout.firstLine + 1;
  const int groups = (layout.lastLine - firstLine + kGroup) / kGroup;
  tbb::parallel_for(0, groups, [&](int group) {
    Scratch& s = scratch.local();
    const int first = firstLine + group * kGroup;
    const int count = std::min(kGroup, layout.lastLine + 1 - first);
    // Each line from its own start (SweepLayout::lineStart).
    int start[kGroup + 1];
    for (int i = 0; i <= count; ++i) {
      walker.reset(s.lines[i]);
      start[i] = layout.startOf(first - 1 + i);
    }
    for (int step = layout.firstStep; step < layout.visitStep; ++step) {
      for (int i = 0; i <= count; ++i) {
        if (step >= start[i]) walker.step(s.lines[i], first - 1 + i, step, false);
      }
    }
    for (int step = layout.visitStep; step < layout.endStep; ++step) {
      for (int i = 0; i <= count; ++i) {
        // Line c serves texels c + floorOffset and the one above it: a
        // window's lines skip the horizon scan where both lie outside it
        // (a line not started yet serves none).
        const int beside = first - 1 + i + layout.floorOffset[step];
        const bool used = beside >= layout.minorBegin - 1 && beside < layout.minorEnd;
        s.horizon[i] =
            step >= start[i] ? walker.step(s.lines[i], first - 1 + i, step, used) : kNoHorizon;
      }
      const int major = layout.start + step * layout.step;
      const double fraction = layout.fraction[step];
      // The group's texels in the window at this step: consecutive minor
      // coordinates, one run.
      HorizonRun run{kMajorIsColumn, major, 0, 0, s.run};
      for (int i = 1; i <= count; ++i) {
        const int minor = first - 1 + i + layout.floorOffset[step];
        if (minor < layout.minorBegin || minor >= layout.minorEnd) continue;
        const int col = kMajorIsColumn ? major : minor;
        const int row = kMajorIsColumn ? minor : major;
        const double lines = blendHorizons(s.horizon[i], s.horizon[i - 1], fraction);
        const double best = std::max(lines, walker.leavingSlope(col, row));
        if (run.count == 0) run.minorFirst = minor;
        s.run[run.count++] = best <= kNoHorizon ? -std::numeric_limits<double>::infinity() : best;
      }
      if (run.count > 0) visitRun(std::as_const(run));
    }
  });
}

}  // namespace detail

// Calls visitRun(run) with the horizons of every texel of the terrain's
// window for the azimuth phi, as sweepHorizons (below) does, a run at a
// time: the texels of a group of lines at one step, which lie side by side
// (HorizonRun). Runs are visited concurrently, none twice.
template <class VisitRun>
void sweepHorizonRuns(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& options,
                      VisitRun&& visitRun) {
  const double ux = std::cos(phi), uy = std::sin(phi);
  const detail::SweepLayout layout =
      detail::makeSweepLayout(terrain, ux, uy, detail::sweepReachM(options));
  if (layout.majorIsColumn) {
    detail::sweepLines<true>(terrain, layout, ux, uy, options, visitRun);
  } else {
    detail::sweepLines<false>(terrain, layout, ux, uy, options, visitRun);
  }
}

// Calls visit(windowIndex, tanHorizon) once for every texel of the
// terrain's window (BakeTerrain::windowIndex) for the azimuth phi (radians,
// counter-clockwise from east; u = (cos phi, sin phi) in the world frame).
// tanHorizon is the tangent of the horizon elevation, -inf when no terrain
// lies ahead. Groups of lines run in parallel: visit is called
// concurrently, but never twice for the same texel.
template <class Visit>
void sweepHorizons(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& options,
                   Visit&& visit) {
  sweepHorizonRuns(terrain, phi, options, [&](const HorizonRun& run) {
    for (int j = 0; j < run.count; ++j) {
      const int minor = run.minorFirst + j;
      visit(run.majorIsColumn ? terrain.windowIndex(run.major, minor)
                              : terrain.windowIndex(minor, run.major),
            run.tanHorizon[j]);
    }
  });
}

}  // namespace aal
