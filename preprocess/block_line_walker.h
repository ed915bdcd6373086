// One group of lines of the block sweep (horizon_blocks.h), walked in
// lockstep. Without a distance limit each line keeps the upper hull of its
// points; with a short one (scansWithinLimit) it keeps the points of its
// last ScanRing::kSteps steps, and each new point's horizon is the steepest
// slope to those within the limit. Instantiated for both layouts in
// block_line_walker.cpp (the scalar walk) and bake_avx2.cpp (the AVX2
// walk); the parts both walks share are here.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/far_horizon.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/horizon_sweep.h"

namespace aal::detail {

struct HullPointF {
  float t, z;  // distance along u (m), height with the curvature drop (m)
};

// Whether the top of a hull of m >= 2 points falls under the line from the
// point below it to a new point (t, z) nearer along the walk: it is popped.
inline bool hullTopUnder(const HullPointF* hull, int m, float t, float z) {
  return (hull[m - 2].z - z) * (hull[m - 1].t - t) >= (hull[m - 1].z - z) * (hull[m - 2].t - t);
}

// clampedEdgeSlope() in single precision, written with selects.
inline float clampedEdgeSlopeF(float rise, float toEdge, float curvature) {
  const float tangentDistance = std::sqrt(std::max(0.0f, -rise) / std::max(curvature, 1e-30f));
  const float curved =
      tangentDistance <= toEdge ? kNoHorizonTangent : -2.0f * std::sqrt(-rise * curvature);
  const float beyond = rise >= 0.0f ? kNoHorizonTangent : (curvature <= 0.0f ? 0.0f : curved);
  return toEdge <= 0.0f ? 0.0f : beyond;
}

// With a short distance limit (scansWithinLimit), a walk's points of its
// last kSteps steps, at [step % kSteps][walked line]: their true heights
// and distances along u (double: the scan's distances are differences of
// them). Such a limit covers at most kBlockScanSteps steps, so the ring
// holds every point within it. Caller-owned, like the hulls: one per
// thread, whatever it held before.
struct ScanRing {
  static constexpr int kSteps = 512;
  static constexpr int kLines = 48;  // BlockLineWalker::kPaddedLines
  static_assert(kSteps > kBlockScanSteps, "the ring holds every point within the limit");
  alignas(32) float z[kSteps][kLines];
  alignas(32) double t[kSteps][kLines];
};

// The points from one line's hull stack to the next's in the walk's
// storage: at least majorLength, an odd number of 64-byte cache lines.
// At a power-of-two length the stacks lay a multiple of 4 KiB apart, so
// that the tops of a group's 48 stacks, which every step reads, shared a
// few of the L1 cache's sets.
inline int hullStride(int majorLength) {
  return (majorLength + 15) / 16 * 16 + 8;
}

// A run of neighbouring lines of one layout, walked in lockstep: per sweep
// step, the texels between consecutive walked lines get their horizon
// tangents (blended between the two lines, at least the leaving slope).
// kMajorIsColumn: lines advance column by column. The hull stacks live in
// caller-owned storage of kMaxLines * hullStride(majorLength) points, and with a
// scanned limit the points in a caller-owned ScanRing.
template <bool kMajorIsColumn>
class BlockLineWalker {
 public:
  // A group's lines, the line before them, and room for the few more an
  // opposite walk needs to cover the same texels (sweepOpposedHorizonBlocks).
  static constexpr int kMaxLines = HorizonBlock::kLines + 4;

  BlockLineWalker(const BakeTerrain& terrain, const SweepLayout& layout, double ux, double uy,
                  const HorizonSweepOptions& options, HullPointF* hulls, ScanRing* ring = nullptr);

  // Starts walking lines firstLine .. firstLine + lines - 1 (lines <=
  // kMaxLines) from the sweep's first step.
  void begin(int firstLine, int lines);
  // Walked line i starts afresh at sweep step `step` (its start,
  // SweepLayout::lineStart), before that step is taken: its hull emptied
  // and, where far is given and the line is on the grid there, filled with
  // the far field's samples beyond that point (FarLineMarch::march, into
  // `distance` and `height`), pushed farthest first as though walked.
  void restart(int i, int step, const FarLineMarch* far, std::vector<float>& distance,
               std::vector<float>& height);

  // Whether any walked line may be on the grid at `step` (with a texel of
  // margin against rounding; a step's texels lie between walked lines, so
  // none are on the grid either where this is false). At other steps step()
  // changes nothing and may be skipped: oblique sweeps have twice as many
  // lines as the grid has rows or columns, and each group is on the grid
  // for only part of the steps (skipping them, with the smaller groups of
  // sweepOpposedHorizonBlocks, made 45° passes 20 % faster at 1024²).
  bool anyLineOnGrid(int step) const {
    const double shift = step * layout_.minorPerStep;
    return firstLine_ + shift <= minorMax_ + 1.0 && firstLine_ + lines_ - 1 + shift >= -1.0;
  }

  // Advances every line by sweep step `step` (steps in order from 0; those
  // where !anyLineOnGrid(step) may be left out) and
  // writes the tangents of the texels with minor coordinates minorLo ..
  // minorHi (on the grid, between walked lines; none when minorLo > minorHi)
  // to out[minor - minorLo], and where east and north are given, their
  // slopes (HorizonBlock::slopeEast, slopeNorth) there; those two have room
  // for HorizonBlock::kPaddedTexels.
  void step(int step, int minorLo, int minorHi, float* out, float* east = nullptr,
            float* north = nullptr);

 private:
  // Per-line arrays run to whole vectors of 8 lines.
  static constexpr int kPaddedLines = (kMaxLines + 7) / 8 * 8;
  static_assert(kPaddedLines == ScanRing::kLines);

  // What a step reads before the hull updates. Index j of the height
  // arrays holds minor coordinate base - 1 + j; index i of lineT, walked
  // line i.
  struct StepSlice {
    int major;
    // Walked line i passes between texels base + i and base + i + 1: the
    // texels between walked lines are base + 1 .. base + lines - 1.
    int base;
    int lineFirst,
        lineLast;       // the walked lines on the grid (none: first > last)
    float w;            // the lines' fraction of a texel past base + i
    bool offGridMajor;  // the cell ahead is off the grid: no leaving slope
    float heights[kPaddedLines + 2], nextSlice[kPaddedLines + 2], backSlice[kPaddedLines + 2];
    float invCellX[kPaddedLines + 2];
    float lineT[kPaddedLines];  // the lines' distances along u
    // In double, as computed: the scan's distances and its limit.
    alignas(32) double lineTD[kPaddedLines];
    // The slopes' neighbours: the slices at major - 1 and major + 1
    // (heights where off the grid) and their difference's scale.
    const float *majorLow, *majorHigh;
    float majorScale;
    float *east, *north;  // null: no slopes wanted
  };

  // The scalar walk's per-line values of a step.
  struct LineValues {
    float z[kPaddedLines], curvedZ[kPaddedLines];
    float riseToNear[kPaddedLines], runToNear[kPaddedLines], horizon[kPaddedLines];
  };

  // restart()'s far samples for walked line i.
  void seedLine(int i, const FarLineMarch& far, int step, std::vector<float>& distance,
                std::vector<float>& height);
  // Both walks: the heights a few steps ahead into the cache.
  [[gnu::always_inline]] inline void prefetchAhead(int step) const;
  // Both walks: the step's slice of the grid, its heights and the slopes'
  // neighbours (slopes only where east and north are given). kAvx2:
  // inlined into stepAvx2, where the loop inside the grid is AVX2 code.
  template <bool kAvx2>
  [[gnu::always_inline]] inline void loadSlice(int step, float* east, float* north,
                                               StepSlice& slice) const;

  // The scalar walk (block_line_walker.cpp). Its steps, and the AVX2
  // walk's, are always inlined into stepScalar and stepAvx2: the step's
  // arrays then stay local to one function, so the compiler knows that no
  // store to them changes the grid or the walker.
  void stepScalar(int step, int minorLo, int minorHi, float* out, float* east, float* north);
  // The scan's part of a step, both walks: each line's new point into the
  // ring, and which earlier points lie within the limit (within_,
  // edgeWithin_, toEdge_); z gets the lines' heights.
  [[gnu::always_inline]] inline void scanPush(int step, const StepSlice& slice, float* z);
  // The scalar scan: the lines' horizons from their points within the limit.
  [[gnu::always_inline]] inline void scanHorizons(int step, const StepSlice& slice, const float* z,
                                                  float* horizon) const;
  [[gnu::always_inline]] inline void lineSamples(int step, StepSlice& slice) const;
  [[gnu::always_inline]] inline void updateHulls(const StepSlice& slice, LineValues& lines);
  [[gnu::always_inline]] inline void lineHorizons(const StepSlice& slice, LineValues& lines) const;
  [[gnu::always_inline]] inline void texelTangents(const StepSlice& slice, const LineValues& lines,
                                                   int minorLo, int minorHi, float* out) const;
  [[gnu::always_inline]] inline void texelSlopes(const StepSlice& slice, int i, int j) const;

#if AAL_HORIZON_AVX2
  // The AVX2 walk (bake_avx2.cpp): line samples, hull updates and texels 4
  // or 8 lines at a time.
  __attribute__((target("avx2"))) void stepAvx2(int step, int minorLo, int minorHi, float* out,
                                                float* east, float* north);
  __attribute__((target("avx2"), always_inline)) inline void lineSamplesAvx2(
      int step, StepSlice& slice) const;
  __attribute__((target("avx2"), always_inline)) inline void updateHullsAvx2(const StepSlice& slice,
                                                                             bool texels,
                                                                             float* lineHorizon);
  __attribute__((target("avx2"), always_inline)) inline void scanHorizonsAvx2(
      int step, const StepSlice& slice, const float* z, float* lineHorizon) const;
  __attribute__((target("avx2"), always_inline)) inline void texelTangentsAvx2(
      const StepSlice& slice, const float* lineHorizon, int minorLo, int minorHi, float* out) const;
  __attribute__((target("avx2"), always_inline)) inline void texelSlopesAvx2(const StepSlice& slice,
                                                                             int i, int j) const;
#endif

  // A line's place along u (m) where it crosses major coordinate `major` at
  // minor coordinate `minor`: the distance the hull points are placed by.
  double lineT(int major, double minor) const {
    return placeAlongU<kMajorIsColumn>(terrain_, major, minor, ux_, uy_);
  }

  // HeightView::at over the heights held, from the walker's own copy of
  // their layout: one subtraction (the whole-DEM bake was 5-9 % slower
  // through a field's at() that offset rows and columns apart).
  const float* heightPointer(int major, int minor) const {
    const ptrdiff_t col = kMajorIsColumn ? major : minor, row = kMajorIsColumn ? minor : major;
    return residentHeights_ + (row * rowStride_ + col - residentOffset_);
  }
  float heightAt(int major, int minor) const {
    return *heightPointer(major, minor);
  }

  const BakeTerrain& terrain_;
  const SweepLayout& layout_;
  const double ux_, uy_;
  HullPointF* const hulls_;
  const float curvature_;
  const bool clampEdge_;
  const double maxDistance_;
  const bool scan_;  // scansWithinLimit
  const int minorMax_;
  const float rowCentre_;
  const bool avx2_;
  // The heights held (terrain.heights: the whole DEM or a window of it):
  // where they start, their row stride, the offset of the first one (its
  // row * stride + its column), and the first and last major and minor
  // coordinates held, for the prefetches.
  const float* residentHeights_;
  ptrdiff_t rowStride_, residentOffset_;
  int residentMajor_[2], residentMinor_[2];
  int dMajorNeighbour_, dMinorNeighbour_;
  float wMajorNeighbour_, wMinorNeighbour_, invCellY_;
  int firstLine_ = 0, lines_ = 0;
  // Per walked line: hull size (0: not started) and the DEM edge ahead.
  alignas(32) int size_[kPaddedLines];
  alignas(32) float edgeT_[kPaddedLines], edgeZ_[kPaddedLines];
  // The AVX2 walk's copy of the top three hull points, hull[size - 1],
  // hull[size - 2] and hull[size - 3]: the first two pop tests of a step
  // need no gather (4 % faster than two at 1024²; most lines pop once).
  alignas(32) float topT_[kPaddedLines], topZ_[kPaddedLines];
  alignas(32) float belowT_[kPaddedLines], belowZ_[kPaddedLines];
  alignas(32) float thirdT_[kPaddedLines], thirdZ_[kPaddedLines];

  // The scan (scan_): each line's last points.
  static constexpr int kScanRing = ScanRing::kSteps;
  ScanRing* const ring_;
  // Where every row's cells are alike, the k-th point back of any line lies
  // k steps' length away: per k, the inverse of that distance (in single
  // precision) and the Earth's drop over it, so that the scan multiplies
  // where it would divide (a division per point and 8 lines was its
  // bottleneck). Elsewhere (geographic grids) the distances come from the
  // ring's positions. Filled up to the steps the limit covers.
  bool uniformSteps_ = false;
  float scanInverse_[kScanRing], scanDrop_[kScanRing];
  // Per line: the step of its farthest point within the limit, how many of
  // its earlier points are within it, whether its first point (the DEM
  // edge ahead, with clamped edges) is, and how far ahead that point lies.
  int firstWithin_[kPaddedLines];
  alignas(32) int within_[kPaddedLines];
  int withinMax_[kPaddedLines / 8];           // the most of each 8 lines
  int withinFewest_[kPaddedLines / 8];        // the fewest of each 8's lines on the grid
  alignas(32) int edgeWithin_[kPaddedLines];  // -1 or 0, a lane mask
  alignas(32) float toEdge_[kPaddedLines];
  double edgeTD_[kPaddedLines];
};

template <bool kMajorIsColumn>
inline void BlockLineWalker<kMajorIsColumn>::prefetchAhead(int step) const {
  // The heights of steps ahead, a row or a column that the hardware
  // prefetcher does not foresee (the previous step's are on the next
  // slice): 6 % faster at 4096², the same at 1024² (in cache anyway).
  // Only the heights held (a window of a DEM read in parts) are
  // prefetched: the steps ahead may leave them.
  const int majorLength = layout_.majorLength, lines = lines_;
  if constexpr (kMajorIsColumn) {
    // A cache line holds 16 columns: every 8 steps, the column 16 on.
    const int ahead = step + 16;
    if ((step & 7) == 0 && ahead < majorLength) {
      const int aheadMajor = layout_.start + ahead * layout_.step;
      const int aheadBase = firstLine_ + layout_.floorOffset[ahead];
      if (aheadMajor < residentMajor_[0] || aheadMajor > residentMajor_[1]) return;
      const int lo = std::max(aheadBase - 1, residentMinor_[0]);
      const int hi = std::min(aheadBase + lines, residentMinor_[1]);
      for (int j = lo; j <= hi; ++j) __builtin_prefetch(heightPointer(aheadMajor, j));
    }
  } else {
    const int ahead = step + 2;
    if (ahead < majorLength) {
      const int aheadMajor = layout_.start + ahead * layout_.step;
      const int aheadBase = firstLine_ + layout_.floorOffset[ahead];
      if (aheadMajor < residentMajor_[0] || aheadMajor > residentMajor_[1]) return;
      const int lo = std::max(aheadBase - 1, residentMinor_[0]);
      const int hi = std::min(aheadBase + lines, residentMinor_[1]);
      if (lo > hi) return;
      const float* row = heightPointer(aheadMajor, lo);
      for (int j = 0; j < hi - lo; j += 16) __builtin_prefetch(row + j);
      __builtin_prefetch(row + (hi - lo));
    }
  }
}

template <bool kMajorIsColumn>
inline void BlockLineWalker<kMajorIsColumn>::scanPush(int step, const StepSlice& slice, float* z) {
  ScanRing& ring = *ring_;
  const int slot = step & (kScanRing - 1);
  const float w = slice.w;
  std::fill(within_, within_ + kPaddedLines, 0);
  std::fill(withinMax_, withinMax_ + kPaddedLines / 8, 0);
  std::fill(withinFewest_, withinFewest_ + kPaddedLines / 8, kScanRing);
  if (clampEdge_) std::fill(edgeWithin_, edgeWithin_ + kPaddedLines, 0);
  for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
    z[i] = (1.0f - w) * slice.heights[i + 1] + w * slice.heights[i + 2];
    const double t = slice.lineTD[i];
    if (size_[i] == 0) {  // the line's first point: its edge ahead
      edgeTD_[i] = t;
      edgeZ_[i] = z[i];
      firstWithin_[i] = step;
    }
    // Points lie farther along u the earlier they were walked (a step
    // advances at least a cell), so those within the limit are the last
    // few: the farthest moves on as the walk does.
    int first = firstWithin_[i];
    while (first < step && ring.t[first & (kScanRing - 1)][i] - t > maxDistance_) ++first;
    firstWithin_[i] = first;
    within_[i] = step - first;
    withinMax_[i / 8] = std::max(withinMax_[i / 8], within_[i]);
    withinFewest_[i / 8] = std::min(withinFewest_[i / 8], within_[i]);
    if (clampEdge_) {
      const double toEdge = edgeTD_[i] - t;
      edgeWithin_[i] = toEdge <= maxDistance_ ? -1 : 0;
      toEdge_[i] = static_cast<float>(toEdge);
    }
    ring.z[slot][i] = z[i];
    ring.t[slot][i] = t;
    ++size_[i];
  }
}

template <bool kMajorIsColumn>
template <bool kAvx2>
inline void BlockLineWalker<kMajorIsColumn>::loadSlice(int step, float* east, float* north,
                                                       StepSlice& slice) const {
  const int lines = lines_, majorLength = layout_.majorLength, minorMax = minorMax_;
  const int major = layout_.start + step * layout_.step;
  const int base = firstLine_ + layout_.floorOffset[step];
  slice.major = major;
  slice.base = base;
  slice.w = static_cast<float>(layout_.fraction[step]);
  slice.east = east;
  slice.north = north;
  // Heights around the lines on this slice and, for the leaving slope, on
  // the next one (clamped to the grid; what lies off it is masked).
  const int nextMajor = major + dMajorNeighbour_;
  const bool haveNextSlice = nextMajor >= 0 && nextMajor < majorLength;
  // The cell ahead is off the grid: no leaving slope
  // (LineWalker::leavingSlope).
  slice.offGridMajor = wMajorNeighbour_ > 0.0f && !haveNextSlice;
  // For the slopes, the slice behind too: the previous step's, in cache.
  const int backMajor = major - dMajorNeighbour_;
  const bool haveBackSlice = slice.east && backMajor >= 0 && backMajor < majorLength;
  float* heights = slice.heights;
  float* nextSlice = slice.nextSlice;
  float* backSlice = slice.backSlice;
  float* invCellX = slice.invCellX;
  if (kAvx2 && base >= 1 && base + lines <= minorMax) {
    // Inside the grid: no clamps, so the loop is vector code.
    for (int j = 0; j < lines + 2; ++j) {
      heights[j] = heightAt(major, base - 1 + j);
      nextSlice[j] = haveNextSlice ? heightAt(nextMajor, base - 1 + j) : 0.0f;
      backSlice[j] = haveBackSlice ? heightAt(backMajor, base - 1 + j) : 0.0f;
      invCellX[j] = static_cast<float>(
          terrain_.rowInvCellX[kMajorIsColumn ? static_cast<size_t>(base - 1 + j) : major]);
    }
  } else {
    for (int j = 0; j < lines + 2; ++j) {
      const int minor = std::clamp(base - 1 + j, 0, minorMax);
      heights[j] = heightAt(major, minor);
      nextSlice[j] = haveNextSlice ? heightAt(nextMajor, minor) : 0.0f;
      backSlice[j] = haveBackSlice ? heightAt(backMajor, minor) : 0.0f;
      invCellX[j] = static_cast<float>(
          terrain_.rowInvCellX[kMajorIsColumn ? static_cast<size_t>(minor) : major]);
    }
  }

  // The slices at major - 1 and major + 1 as BakeTerrain::slopeEastAt and
  // slopeNorthAt read them: clamped to the grid.
  const float* ahead = haveNextSlice ? nextSlice : heights;
  const float* behind = haveBackSlice ? backSlice : heights;
  slice.majorLow = dMajorNeighbour_ > 0 ? behind : ahead;
  slice.majorHigh = dMajorNeighbour_ > 0 ? ahead : behind;
  slice.majorScale =
      BakeTerrain::differenceScale(std::max(major - 1, 0), std::min(major + 1, majorLength - 1));
}

}  // namespace aal::detail
