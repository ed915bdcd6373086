// The line sweep of horizon_sweep.h, restructured for speed: the same lines,
// hulls and blending, but each step of a group of lines hands the horizons
// of its texels over as one block, and the arithmetic runs in single
// precision in loops over the group that the compiler turns into vector
// code. Only the hull update (a stack pop loop per line) stays scalar.
// Without a distance limit only: sweepHorizons() remains the general path
// and the reference this one is tested against. sweepOpposedHorizonBlocks()
// hands over azimuths phi and phi + pi together, so that a bake touches a
// texel's sums once for both.
//
// Single precision: distances along a line are at most ~350 km from the DEM
// centre even for 16384 x 30 m grids, where a float is good to 3 cm; the
// tangents that come out are within ~1e-4 of the double-precision sweep's.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "bake_terrain.h"
#include "horizon_sweep.h"

namespace aal {

// The texels of one sweep step of one group of lines: texel j (0 <= j <
// count) is firstTexel + j * stride in the heightfield, with horizon
// tangent tanHorizon[j] (kNoHorizonTangent when no terrain lies ahead).
struct HorizonBlock {
  // Lines stepped together; a block is up to kLines texels. 32 beat 16 by
  // 3 % at 1024² and 10 % at 4096² (fewer groups, so fewer passes over each
  // column's cache lines); 64 was slower at 1024² (docs/performance.md).
  static constexpr int kLines = 32;
  size_t firstTexel = 0;
  ptrdiff_t stride = 1;
  int count = 0;
  const float* tanHorizon = nullptr;
  // The same group's texels kAheadSteps steps later (aheadCount 0: none),
  // for the visitor to prefetch what it will touch there.
  static constexpr int kAheadSteps = 6;
  size_t aheadFirstTexel = 0;
  int aheadCount = 0;
  // sweepOpposedHorizonBlocks: the tangents of the opposite azimuth.
  const float* tanOpposite = nullptr;
};

// Finite stand-in for -infinity: keeps the vector loops free of inf tests.
constexpr float kNoHorizonTangent = -1e30f;

namespace detail {

struct HullPointF {
  float t, z;  // distance along u (m), height with the curvature drop (m)
};

// clampedEdgeSlope() in single precision, written with selects.
inline float clampedEdgeSlopeF(float rise, float toEdge, float curvature) {
  const float tangentDistance = std::sqrt(std::max(0.0f, -rise) / std::max(curvature, 1e-30f));
  const float curved =
      tangentDistance <= toEdge ? kNoHorizonTangent : -2.0f * std::sqrt(-rise * curvature);
  const float beyond = rise >= 0.0f ? kNoHorizonTangent : (curvature <= 0.0f ? 0.0f : curved);
  return toEdge <= 0.0f ? 0.0f : beyond;
}

// A run of neighbouring lines of one layout, walked in lockstep: per sweep
// step, the texels between consecutive walked lines get their horizon
// tangents (blended between the two lines, at least the leaving slope).
// kMajorIsColumn: lines advance column by column. The hull stacks live in
// caller-owned storage of kMaxLines * majorLength points.
template <bool kMajorIsColumn>
class BlockLineWalker {
 public:
  // A group's lines, the line before them, and room for the few more an
  // opposite walk needs to cover the same texels (sweepOpposedHorizonBlocks).
  static constexpr int kMaxLines = HorizonBlock::kLines + 4;

  BlockLineWalker(const BakeTerrain& terrain, const SweepLayout& layout, double ux, double uy,
                  const HorizonSweepOptions& options, HullPointF* hulls)
      : terrain_(terrain),
        field_(*terrain.field),
        layout_(layout),
        ux_(ux),
        uy_(uy),
        hulls_(hulls),
        curvature_(static_cast<float>(options.curvature)),
        clampEdge_(options.clampEdge),
        minorMax_(layout.minorLength - 1),
        rowCentre_(0.5f * static_cast<float>(terrain.height - 1)) {
    // The bilinear surface leaving a texel (LineWalker::leavingSlope): one
    // neighbour lies on the next major slice, the other beside it on the
    // same slice.
    const int dCol = ux > 0 ? 1 : -1, dRow = uy > 0 ? -1 : 1;  // rows grow south
    const float wx = std::abs(ux) > 1e-12 ? static_cast<float>(std::abs(ux)) : 0.0f;
    const float wy = std::abs(uy) > 1e-12 ? static_cast<float>(std::abs(uy)) : 0.0f;
    dMajorNeighbour_ = kMajorIsColumn ? dCol : dRow;
    dMinorNeighbour_ = kMajorIsColumn ? dRow : dCol;
    wMajorNeighbour_ = kMajorIsColumn ? wx : wy;
    wMinorNeighbour_ = kMajorIsColumn ? wy : wx;
    invCellY_ = static_cast<float>(1.0 / terrain.cellY);
  }

  // Starts walking lines firstLine .. firstLine + lines - 1 (lines <=
  // kMaxLines) from the sweep's first step.
  void begin(int firstLine, int lines) {
    firstLine_ = firstLine;
    lines_ = lines;
    for (int i = 0; i < lines; ++i) {
      size_[i] = 0;
      started_[i] = false;
    }
  }

  // Advances every line by sweep step `step` (steps in order from 0) and
  // writes the tangents of the texels with minor coordinates minorLo ..
  // minorHi (on the grid, between walked lines; none when minorLo > minorHi)
  // to out[minor - minorLo].
  void step(int step, int minorLo, int minorHi, float* out);

 private:
  float heightAt(int major, int minor) const {
    return kMajorIsColumn ? field_.at(major, minor) : field_.at(minor, major);
  }

  const BakeTerrain& terrain_;
  const Heightfield& field_;
  const SweepLayout& layout_;
  const double ux_, uy_;
  HullPointF* const hulls_;
  const float curvature_;
  const bool clampEdge_;
  const int minorMax_;
  const float rowCentre_;
  int dMajorNeighbour_, dMinorNeighbour_;
  float wMajorNeighbour_, wMinorNeighbour_, invCellY_;
  int firstLine_ = 0, lines_ = 0;
  // Per walked line.
  int size_[kMaxLines];
  bool started_[kMaxLines];
  float edgeT_[kMaxLines], edgeZ_[kMaxLines];
};

template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::step(int step, int minorLo, int minorHi, float* out) {
  constexpr int kMax = kMaxLines;
  const int lines = lines_, majorLength = layout_.majorLength, minorMax = minorMax_;
  const float curvature = curvature_;
  const int major = layout_.start + step * layout_.step;
  // Walked line i passes between texels base + i and base + i + 1: the
  // texels between walked lines are base + 1 .. base + lines - 1.
  const int base = firstLine_ + layout_.floorOffset[step];
  const float w = static_cast<float>(layout_.fraction[step]);

  // Per step, index j of these holds minor coordinate base - 1 + j.
  float heights[kMax + 2], nextSlice[kMax + 2], invCellX[kMax + 2];
  float lineT[kMax], lineZ[kMax], lineCurvedZ[kMax];
  float riseToNear[kMax], runToNear[kMax], lineHorizon[kMax];

  // Heights around the lines on this slice and, for the leaving slope, on
  // the next one (clamped to the grid; what lies off it is masked).
  const int nextMajor = major + dMajorNeighbour_;
  const bool haveNextSlice = nextMajor >= 0 && nextMajor < majorLength;
  // The cell ahead is off the grid: no leaving slope (LineWalker::leavingSlope).
  const bool offGridMajor = wMajorNeighbour_ > 0.0f && !haveNextSlice;
  for (int j = 0; j < lines + 2; ++j) {
    const int minor = std::clamp(base - 1 + j, 0, minorMax);
    heights[j] = heightAt(major, minor);
    nextSlice[j] = haveNextSlice ? heightAt(nextMajor, minor) : 0.0f;
    invCellX[j] = static_cast<float>(
        terrain_.rowInvCellX[kMajorIsColumn ? static_cast<size_t>(minor) : major]);
  }

  // Line samples: distance along u and height, linear across the line.
  int lineFirst = lines, lineLast = -1;
  for (int i = 0; i < lines; ++i) {
    const double minor = (firstLine_ + i) + step * layout_.minorPerStep;
    if (minor < 0.0 || minor > minorMax) continue;
    lineFirst = std::min(lineFirst, i);
    lineLast = i;
    double t;
    if constexpr (kMajorIsColumn) {
      const int nearRow = std::min(static_cast<int>(minor + 0.5), minorMax);
      t = (major - terrain_.centreCol) * terrain_.rowCellX[nearRow] * ux_ +
          (rowCentre_ - minor) * terrain_.cellY * uy_;
    } else {
      t = (minor - terrain_.centreCol) * terrain_.rowCellX[major] * ux_ + terrain_.y(major) * uy_;
    }
    lineT[i] = static_cast<float>(t);
  }
  for (int i = lineFirst; i <= lineLast; ++i) {
    lineZ[i] = (1.0f - w) * heights[i + 1] + w * heights[i + 2];
    lineCurvedZ[i] = lineZ[i] - curvature * lineT[i] * lineT[i];
  }

  // Hull update, line by line: pop what falls under the new point, and the
  // point left behind it is the tangent point of its horizon.
  for (int i = lineFirst; i <= lineLast; ++i) {
    HullPointF* hull = hulls_ + static_cast<size_t>(i) * majorLength;
    const float t = lineT[i], z = lineCurvedZ[i];
    if (!started_[i]) {
      started_[i] = true;
      edgeT_[i] = t;
      edgeZ_[i] = lineZ[i];
    }
    // Pops are rare beyond two per step: the first two are tested without
    // branches (which mispredict here), the loop takes the rest.
    const auto under = [&](int m) {
      return (hull[m - 2].z - z) * (hull[m - 1].t - t) >= (hull[m - 1].z - z) * (hull[m - 2].t - t);
    };
    int n = size_[i];
    n -= (n >= 2 && under(n)) ? 1 : 0;
    n -= (n >= 2 && under(n)) ? 1 : 0;
    while (n >= 2 && under(n)) --n;
    // No point ahead: a stand-in that gives kNoHorizonTangent below.
    riseToNear[i] = n >= 1 ? hull[n - 1].z - z : kNoHorizonTangent;
    runToNear[i] = n >= 1 ? hull[n - 1].t - t : 1.0f;
    hull[n] = {t, z};
    size_[i] = n + 1;
  }
  if (minorLo > minorHi) return;  // the step only fills the hulls

  for (int i = lineFirst; i <= lineLast; ++i) {
    const float slope = riseToNear[i] / runToNear[i];
    lineHorizon[i] =
        slope <= kNoHorizonTangent ? kNoHorizonTangent : slope + 2.0f * curvature * lineT[i];
  }
  if (clampEdge_) {
    for (int i = lineFirst; i <= lineLast; ++i) {
      lineHorizon[i] = std::max(
          lineHorizon[i], clampedEdgeSlopeF(edgeZ_[i] - lineZ[i], edgeT_[i] - lineT[i], curvature));
    }
  }
  for (int i = 0; i < lineFirst; ++i) lineHorizon[i] = kNoHorizonTangent;
  for (int i = std::max(lineLast + 1, 0); i < lines; ++i) lineHorizon[i] = kNoHorizonTangent;

  // The texels: blend their two lines, at least the leaving slope.
  const int texelFirst = minorLo - base, texelLast = minorHi - base;
  for (int i = texelFirst; i <= texelLast; ++i) {
    const float nearLine = lineHorizon[i], farLine = lineHorizon[i - 1];
    const float blended = nearLine + w * (farLine - nearLine);
    const float blend = (farLine <= kNoHorizonTangent || w == 0.0f) ? nearLine
                        : nearLine <= kNoHorizonTangent             ? farLine
                                                                    : blended;
    const float own = heights[i + 1];
    const float invCellMajor = kMajorIsColumn ? invCellX[i + 1] : invCellY_;
    const float invCellMinor = kMajorIsColumn ? invCellY_ : invCellX[i + 1];
    const float leaving =
        wMajorNeighbour_ * (nextSlice[i + 1] - own) * invCellMajor +
        wMinorNeighbour_ * (heights[i + 1 + dMinorNeighbour_] - own) * invCellMinor;
    const int minorNeighbour = base + i + dMinorNeighbour_;
    const bool offGrid = offGridMajor || (wMinorNeighbour_ > 0.0f &&
                                          (minorNeighbour < 0 || minorNeighbour > minorMax));
    out[i - texelFirst] = std::max(blend, offGrid ? kNoHorizonTangent : leaving);
  }
}

// The texels a group of lines hands over at each step, and what the blocks
// point at.
template <bool kMajorIsColumn>
struct GroupTexels {
  const SweepLayout& layout;
  ptrdiff_t width;   // of the field
  int first, count;  // the group's lines first .. first + count - 1

  // Minor range of the group's texels at `step` (empty: lo > hi): those
  // between its lines (and the line before them), on the grid.
  std::pair<int, int> at(int step) const {
    const int base = first - 1 + layout.floorOffset[step];
    return {std::max(base + 1, 0), std::min(base + count, layout.minorLength - 1)};
  }
  size_t texel(int step, int minor) const {
    const ptrdiff_t major = layout.start + step * layout.step;
    return static_cast<size_t>(kMajorIsColumn ? minor * width + major : major * width + minor);
  }
  // The block of `step`, with its texels kAheadSteps later.
  HorizonBlock block(int step, const float* tanHorizon) const {
    const auto [lo, hi] = at(step);
    HorizonBlock b;
    b.firstTexel = texel(step, lo);
    b.stride = kMajorIsColumn ? width : 1;
    b.count = hi - lo + 1;
    b.tanHorizon = tanHorizon;
    const int ahead = step + HorizonBlock::kAheadSteps;
    if (ahead < layout.majorLength) {
      const auto [aheadLo, aheadHi] = at(ahead);
      b.aheadFirstTexel = texel(ahead, aheadLo);
      b.aheadCount = std::max(0, aheadHi - aheadLo + 1);
    }
    return b;
  }
};

struct BlockScratch {
  std::vector<HullPointF> hulls;  // kMaxLines stacks of majorLength points
  std::vector<float> opposite;    // kLines tangents per step
};

template <bool kMajorIsColumn, class VisitBlock>
void sweepBlocks(const BakeTerrain& terrain, const SweepLayout& layout, double ux, double uy,
                 const HorizonSweepOptions& options, VisitBlock& visit) {
  constexpr int kLines = HorizonBlock::kLines;
  using Walker = BlockLineWalker<kMajorIsColumn>;
  const int majorLength = layout.majorLength;
  tbb::enumerable_thread_specific<BlockScratch> scratch;

  // As in sweepLines: texel (k, line + floorOffset[k]) lies between lines
  // c - 1 and c, so each group also walks the line just before it.
  const int firstLine = layout.firstLine + 1;
  const int groups = (layout.lastLine - firstLine + kLines) / kLines;
  tbb::parallel_for(0, groups, [&](int group) {
    BlockScratch& s = scratch.local();
    s.hulls.resize(static_cast<size_t>(Walker::kMaxLines) * majorLength);
    const int first = firstLine + group * kLines;
    const GroupTexels<kMajorIsColumn> texels{layout, terrain.field->width, first,
                                             std::min(kLines, layout.lastLine + 1 - first)};
    Walker walker(terrain, layout, ux, uy, options, s.hulls.data());
    walker.begin(first - 1, texels.count + 1);
    float tanHorizon[kLines];
    for (int step = 0; step < majorLength; ++step) {
      const auto [lo, hi] = texels.at(step);
      walker.step(step, lo, hi, tanHorizon);
      if (lo <= hi) visit(texels.block(step, tanHorizon));
    }
  });
}

// Both azimuths at once: lines of `layout` (u = (ux, uy)) in groups as in
// sweepBlocks, and for each group the lines of `opposite` (the layout of -u)
// that pass beside the same texels, walked first, their tangents kept per
// step. `range` is the spread of the opposite lines' offsets against the
// group's (oppositeLines()).
template <bool kMajorIsColumn, class VisitBlock>
void sweepOpposedBlocks(const BakeTerrain& terrain, const SweepLayout& layout,
                        const SweepLayout& opposite, double ux, double uy, double oppositeUx,
                        double oppositeUy, const HorizonSweepOptions& options, VisitBlock& visit) {
  constexpr int kLines = HorizonBlock::kLines;
  using Walker = BlockLineWalker<kMajorIsColumn>;
  const int majorLength = layout.majorLength;
  tbb::enumerable_thread_specific<BlockScratch> scratch;

  const int firstLine = layout.firstLine + 1;
  const int groups = (layout.lastLine - firstLine + kLines) / kLines;
  tbb::parallel_for(0, groups, [&](int group) {
    BlockScratch& s = scratch.local();
    s.hulls.resize(static_cast<size_t>(Walker::kMaxLines) * majorLength);
    s.opposite.resize(static_cast<size_t>(kLines) * majorLength);
    const int first = firstLine + group * kLines;
    const GroupTexels<kMajorIsColumn> texels{layout, terrain.field->width, first,
                                             std::min(kLines, layout.lastLine + 1 - first)};

    // Step k of this sweep is step majorLength - 1 - k of the opposite one
    // (the same slice). Texel minor m lies between opposite lines
    // m - floorOffset - 1 and m - floorOffset there.
    int oppositeFirst = std::numeric_limits<int>::max();
    int oppositeLast = std::numeric_limits<int>::min();
    for (int k = 0; k < majorLength; ++k) {
      const auto [lo, hi] = texels.at(k);
      if (lo > hi) continue;
      const int offset = opposite.floorOffset[majorLength - 1 - k];
      oppositeFirst = std::min(oppositeFirst, lo - offset - 1);
      oppositeLast = std::max(oppositeLast, hi - offset);
    }
    if (oppositeFirst > oppositeLast) return;  // no texels
    Walker backward(terrain, opposite, oppositeUx, oppositeUy, options, s.hulls.data());
    backward.begin(oppositeFirst, oppositeLast - oppositeFirst + 1);
    for (int k = majorLength - 1; k >= 0; --k) {
      const auto [lo, hi] = texels.at(k);
      backward.step(majorLength - 1 - k, lo, hi,
                    s.opposite.data() + static_cast<size_t>(k) * kLines);
    }

    Walker forward(terrain, layout, ux, uy, options, s.hulls.data());
    forward.begin(first - 1, texels.count + 1);
    float tanHorizon[kLines];
    for (int step = 0; step < majorLength; ++step) {
      const auto [lo, hi] = texels.at(step);
      forward.step(step, lo, hi, tanHorizon);
      if (lo > hi) continue;
      HorizonBlock block = texels.block(step, tanHorizon);
      block.tanOpposite = s.opposite.data() + static_cast<size_t>(step) * kLines;
      visit(block);
    }
  });
}

// Lines the opposite walk of sweepOpposedBlocks needs per group at most:
// the group's texels' spread of offsets between the two layouts, plus the
// group's lines and the one before. 0 when the layouts do not pair (the
// lines advance along different axes).
inline int oppositeLines(const SweepLayout& layout, const SweepLayout& opposite) {
  if (layout.majorIsColumn != opposite.majorIsColumn ||
      layout.majorLength != opposite.majorLength) {
    return 0;
  }
  const int n = layout.majorLength;
  int lo = std::numeric_limits<int>::max(), hi = std::numeric_limits<int>::min();
  for (int k = 0; k < n; ++k) {
    const int d = layout.floorOffset[k] - opposite.floorOffset[n - 1 - k];
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return HorizonBlock::kLines + 1 + (hi - lo);
}

}  // namespace detail

// Calls visit(const HorizonBlock&) for the texels of every step of every
// group of lines of azimuth phi (as sweepHorizons(): each texel exactly once,
// blocks concurrently). No distance limit: options.maxDistanceM must be 0.
template <class VisitBlock>
void sweepHorizonBlocks(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& options,
                        VisitBlock&& visit) {
  const double ux = std::cos(phi), uy = std::sin(phi);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy);
  if (layout.majorIsColumn) {
    detail::sweepBlocks<true>(terrain, layout, ux, uy, options, visit);
  } else {
    detail::sweepBlocks<false>(terrain, layout, ux, uy, options, visit);
  }
}

// The same for two opposite azimuths phi and phiOpposite (phi + pi, as the
// caller computes it) in one pass: each block holds both azimuths'
// tangents of its texels (tanHorizon for phi, tanOpposite for phiOpposite),
// so a visitor reads and writes a texel's sums once for both. Each line of
// either azimuth is still walked from its own far end: the opposite walk of
// a group goes first and its tangents wait in a buffer of one float per
// step and line. Returns false, having visited nothing, where the two
// sweeps' lines do not pair up (their major axes differ, at exactly 45
// degrees): then sweep each azimuth on its own.
template <class VisitBlock>
bool sweepOpposedHorizonBlocks(const BakeTerrain& terrain, double phi, double phiOpposite,
                               const HorizonSweepOptions& options, VisitBlock&& visit) {
  const double ux = std::cos(phi), uy = std::sin(phi);
  const double oppositeUx = std::cos(phiOpposite), oppositeUy = std::sin(phiOpposite);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy);
  const detail::SweepLayout opposite = detail::makeSweepLayout(terrain, oppositeUx, oppositeUy);
  const int lines = detail::oppositeLines(layout, opposite);
  if (lines < 1 || lines > detail::BlockLineWalker<true>::kMaxLines) return false;
  if (layout.majorIsColumn) {
    detail::sweepOpposedBlocks<true>(terrain, layout, opposite, ux, uy, oppositeUx, oppositeUy,
                                     options, visit);
  } else {
    detail::sweepOpposedBlocks<false>(terrain, layout, opposite, ux, uy, oppositeUx, oppositeUy,
                                      options, visit);
  }
  return true;
}

}  // namespace aal
