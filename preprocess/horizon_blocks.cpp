// The block sweeps of horizon_blocks.h: the lines of an azimuth in groups,
// one task per group, each group walked by a BlockLineWalker
// (block_line_walker.h).
#include "aperture/preprocess/horizon_blocks.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include "aperture/preprocess/block_line_walker.h"
#include "aperture/preprocess/far_horizon.h"

namespace aal {

namespace detail {

namespace {

// setHorizonAvx2Allowed(): off, the scalar paths run even where AVX2 would.
std::atomic<bool> horizonAvx2Allowed{true};

// A step's slopes (HorizonBlock::slopeEast, slopeNorth), zeroed once so
// that the vector loops never meet stale lanes.
struct BlockSlopes {
  alignas(32) float east[HorizonBlock::kPaddedTexels] = {};
  alignas(32) float north[HorizonBlock::kPaddedTexels] = {};
};

// One thread's storage for the walks of its groups.
struct BlockScratch {
  std::vector<HullPointF> hulls;              // kMaxLines stacks, hullStride apart
  std::vector<float> opposite;                // kLines tangents per step
  std::vector<float> farDistance, farHeight;  // a line's far samples (restart)
  std::unique_ptr<ScanRing> ring;             // a scanned limit's points
};

// A step's block: count texels from firstTexel, stride apart, with the
// step's tangents and slopes (and no texels ahead yet).
HorizonBlock stepBlock(size_t firstTexel, ptrdiff_t stride, int count, const float* tanHorizon,
                       const BlockSlopes& slopes) {
  HorizonBlock b;
  b.firstTexel = firstTexel;
  b.stride = stride;
  b.count = count;
  b.tanHorizon = tanHorizon;
  b.slopeEast = slopes.east;
  b.slopeNorth = slopes.north;
  return b;
}

// The sweep of one azimuth: its layout and direction u = (ux, uy).
struct BlockSweep {
  const BakeTerrain& terrain;
  const SweepLayout& layout;
  double ux, uy;
  const HorizonSweepOptions& options;
  // The window sweep's far field: its lines start with it in their hulls.
  const FarLineMarch* far = nullptr;
};

// The texels a group of lines hands over at each step, and what the blocks
// point at.
template <bool kMajorIsColumn>
struct GroupTexels {
  const SweepLayout& layout;
  ptrdiff_t pitch;   // of the field's sums (BakeTerrain::windowIndex)
  int first, count;  // the group's lines first .. first + count - 1

  // Minor range of the group's texels at `step` (empty: lo > hi): those
  // between its lines (and the line before them), on the grid.
  std::pair<int, int> at(int step) const {
    const int base = first - 1 + layout.floorOffset[step];
    return {std::max(base + 1, 0), std::min(base + count, layout.minorLength - 1)};
  }
  size_t texel(int step, int minor) const {
    const ptrdiff_t major = layout.start + step * layout.step;
    return static_cast<size_t>(kMajorIsColumn ? minor * pitch + major : major * pitch + minor);
  }
  // The block of `step`, with its texels kAheadSteps later.
  HorizonBlock block(int step, const float* tanHorizon, const BlockSlopes& slopes) const {
    const auto [lo, hi] = at(step);
    HorizonBlock b =
        stepBlock(texel(step, lo), kMajorIsColumn ? pitch : 1, hi - lo + 1, tanHorizon, slopes);
    const int ahead = step + HorizonBlock::kAheadSteps;
    if (ahead < layout.majorLength) {
      const auto [aheadLo, aheadHi] = at(ahead);
      b.aheadFirstTexel = texel(ahead, aheadLo);
      b.aheadCount = std::max(0, aheadHi - aheadLo + 1);
    }
    return b;
  }
};

// Calls walkGroup(texels, scratch) for every group of groupLines (<=
// kLines) lines of the sweep, concurrently, with the thread's scratch and
// its hulls sized for the sweep.
template <bool kMajorIsColumn, class WalkGroup>
void forEachGroup(const BlockSweep& sweep, int groupLines, WalkGroup&& walkGroup) {
  const SweepLayout& layout = sweep.layout;
  tbb::enumerable_thread_specific<BlockScratch> scratch;
  // As in sweepLines: texel (k, line + floorOffset[k]) lies between lines
  // c - 1 and c, so each group also walks the line just before it.
  const int firstLine = layout.firstLine + 1;
  const int groups = (layout.lastLine - firstLine + groupLines) / groupLines;
  const bool scan = scansWithinLimit(sweep.terrain, sweep.options);
  tbb::parallel_for(0, groups, [&](int group) {
    BlockScratch& s = scratch.local();
    s.hulls.resize(static_cast<size_t>(BlockLineWalker<kMajorIsColumn>::kMaxLines) *
                   hullStride(layout.majorLength));
    if (scan && !s.ring) s.ring = std::make_unique<ScanRing>();
    const int first = firstLine + group * groupLines;
    const GroupTexels<kMajorIsColumn> texels{layout, sweep.terrain.pitch, first,
                                             std::min(groupLines, layout.lastLine + 1 - first)};
    walkGroup(texels, s);
  });
}

// Where a walk's lines start (SweepLayout::lineStart): the walk at the
// earliest, and each line afresh at its own, with its far samples
// (BlockLineWalker::restart), so that a line's tangents do not depend on the
// lines walked with it.
struct LineStarts {
  static constexpr int kMaxLines = BlockLineWalker<true>::kMaxLines;
  int count = 0, next = 0;
  std::pair<int, int> line[kMaxLines];  // (step, walked line), by step

  LineStarts(const SweepLayout& layout, int firstLine, int lines) : count(lines) {
    for (int i = 0; i < lines; ++i) line[i] = {layout.startOf(firstLine + i), i};
    std::sort(line, line + count);
  }
  int first() const { return line[0].first; }

  // Starts the lines that start at `step` (every step in order from
  // first(), whether taken or not).
  template <bool kMajorIsColumn>
  void start(int step, BlockLineWalker<kMajorIsColumn>& walker, const FarLineMarch* far,
             BlockScratch& s) {
    for (; next < count && line[next].first == step; ++next) {
      walker.restart(line[next].second, step, far, s.farDistance, s.farHeight);
    }
  }
};

// Walks a group's own lines (and the one before them) from their starts
// (LineStarts) to endStep: where texelsAt(step) is a range lo .. hi that is
// not empty, the step's texels' tangents and slopes go to
// visitStep(step, lo, hi, tanHorizon, slopes); elsewhere the step only
// fills the hulls.
template <bool kMajorIsColumn, class TexelsAt, class VisitStep>
void walkGroup(const BlockSweep& sweep, const GroupTexels<kMajorIsColumn>& texels, BlockScratch& s,
               int endStep, TexelsAt&& texelsAt, VisitStep&& visitStep) {
  BlockLineWalker<kMajorIsColumn> walker(sweep.terrain, sweep.layout, sweep.ux, sweep.uy,
                                         sweep.options, s.hulls.data(), s.ring.get());
  walker.begin(texels.first - 1, texels.count + 1);
  LineStarts starts(sweep.layout, texels.first - 1, texels.count + 1);
  float tanHorizon[HorizonBlock::kLines];
  BlockSlopes slopes;
  for (int step = starts.first(); step < endStep; ++step) {
    starts.start(step, walker, sweep.far, s);
    if (!walker.anyLineOnGrid(step)) continue;
    const auto [lo, hi] = texelsAt(step);
    walker.step(step, lo, hi, tanHorizon, slopes.east, slopes.north);
    if (lo <= hi) visitStep(step, lo, hi, tanHorizon, slopes);
  }
}

template <bool kMajorIsColumn>
void sweepBlocks(const BlockSweep& sweep, const HorizonBlockVisitor& visit) {
  forEachGroup<kMajorIsColumn>(
      sweep, HorizonBlock::kLines, [&](const auto& texels, BlockScratch& s) {
        walkGroup(
            sweep, texels, s, sweep.layout.majorLength, [&](int step) { return texels.at(step); },
            [&](int step, int, int, const float* tanHorizon, const BlockSlopes& slopes) {
              visit(texels.block(step, tanHorizon, slopes));
            });
      });
}

// A group's texels inside a partial window at each step: empty before the
// window's first step (those steps only fill the hulls).
template <bool kMajorIsColumn>
struct WindowTexels {
  const SweepLayout& layout;
  const GroupTexels<kMajorIsColumn>& texels;

  std::pair<int, int> at(int step) const {
    auto [lo, hi] = texels.at(step);
    if (step < layout.visitStep) hi = lo - 1;
    return {std::max(lo, layout.minorBegin), std::min(hi, layout.minorEnd - 1)};
  }
};

// The first and last of steps [from, to) where texelsAt(step) is not empty
// (first > last: none), as walkOpposite finds them. A group's window texels
// lie on consecutive steps (a band of lines across a rectangle): its walk
// ends at the last, since the steps past it visit nothing.
template <class TexelsAt>
std::pair<int, int> visitedSteps(int from, int to, TexelsAt&& texelsAt) {
  int first = to, last = from - 1;
  for (int step = from; step < to; ++step) {
    const auto [lo, hi] = texelsAt(step);
    if (lo > hi) continue;
    first = std::min(first, step);
    last = step;
  }
  return {first, last};
}

// The block of window texels lo .. hi at `step`, indexed as
// BakeTerrain::windowIndex, with the texels kAheadSteps on.
template <bool kMajorIsColumn>
HorizonBlock windowBlock(const BlockSweep& sweep, const WindowTexels<kMajorIsColumn>& window,
                         int step, int lo, int hi, const float* tanHorizon,
                         const BlockSlopes& slopes) {
  const SweepLayout& layout = sweep.layout;
  const BakeTerrain& terrain = sweep.terrain;
  const int major = layout.start + step * layout.step;
  HorizonBlock b =
      stepBlock(kMajorIsColumn ? terrain.windowIndex(major, lo) : terrain.windowIndex(lo, major),
                kMajorIsColumn ? terrain.pitch : 1, hi - lo + 1, tanHorizon, slopes);
  // The texels kAheadSteps on, for the visitor's prefetches: without them
  // a tile's column passes wait on memory.
  const int ahead = step + HorizonBlock::kAheadSteps;
  if (ahead < layout.endStep) {
    const auto [aheadLo, aheadHi] = window.at(ahead);
    if (aheadLo <= aheadHi) {
      const int aheadMajor = layout.start + ahead * layout.step;
      b.aheadFirstTexel = kMajorIsColumn ? terrain.windowIndex(aheadMajor, aheadLo)
                                         : terrain.windowIndex(aheadLo, aheadMajor);
      b.aheadCount = aheadHi - aheadLo + 1;
    }
  }
  return b;
}

// sweepBlocks for a partial window without a distance limit (a far-field
// bake, far_horizon.h): each of the window's lines walked from
// options.windowReachM before the first window texel it passes beside
// (SweepLayout::lineStart), starting with the far field's samples where
// sweep.far is given, to the last step with a texel of its group; blocks
// only of the window's texels, indexed as BakeTerrain::windowIndex.
template <bool kMajorIsColumn>
void sweepWindowBlocks(const BlockSweep& sweep, const HorizonBlockVisitor& visit) {
  const SweepLayout& layout = sweep.layout;
  forEachGroup<kMajorIsColumn>(
      sweep, HorizonBlock::kLines, [&](const auto& texels, BlockScratch& s) {
        const WindowTexels<kMajorIsColumn> window{layout, texels};
        const auto texelsAt = [&](int step) { return window.at(step); };
        const auto [first, last] = visitedSteps(layout.visitStep, layout.endStep, texelsAt);
        if (first > last) return;
        walkGroup(
            sweep, texels, s, last + 1, texelsAt,
            [&](int step, int lo, int hi, const float* tanHorizon, const BlockSlopes& slopes) {
              visit(windowBlock(sweep, window, step, lo, hi, tanHorizon, slopes));
            });
      });
}

// Step k of `sweep` is step majorLength - 1 - k of the opposite sweep (the
// same slice): walks the opposite lines that pass beside a group's texels
// at steps [visitFirst, visitEnd) (texelsAt(k), as the group's walk visits
// them) backwards over the steps, each from its start in the opposite
// layout (with its far samples where opposite.far is given) to the first
// of those steps with texels, and leaves their tangents in s.opposite,
// kLines per step k. Texel minor m lies between opposite lines
// m - floorOffset - 1 and m - floorOffset there. Returns the first and last
// step k with texels (first > last: none, nothing walked): the group's own
// walk ends there too (visitedSteps).
template <bool kMajorIsColumn, class TexelsAt>
std::pair<int, int> walkOpposite(const BlockSweep& opposite, int visitFirst, int visitEnd,
                                 TexelsAt&& texelsAt, BlockScratch& s) {
  const SweepLayout& layout = opposite.layout;
  const int majorLength = layout.majorLength;
  int oppositeFirst = std::numeric_limits<int>::max();
  int oppositeLast = std::numeric_limits<int>::min();
  int first = visitEnd, last = visitFirst - 1;
  for (int k = visitFirst; k < visitEnd; ++k) {
    const auto [lo, hi] = texelsAt(k);
    if (lo > hi) continue;
    const int offset = layout.floorOffset[majorLength - 1 - k];
    oppositeFirst = std::min(oppositeFirst, lo - offset - 1);
    oppositeLast = std::max(oppositeLast, hi - offset);
    first = std::min(first, k);
    last = k;
  }
  if (first > last) return {first, last};
  s.opposite.resize(static_cast<size_t>(HorizonBlock::kLines) * majorLength);
  BlockLineWalker<kMajorIsColumn> backward(opposite.terrain, layout, opposite.ux, opposite.uy,
                                           opposite.options, s.hulls.data(), s.ring.get());
  backward.begin(oppositeFirst, oppositeLast - oppositeFirst + 1);
  LineStarts starts(layout, oppositeFirst, oppositeLast - oppositeFirst + 1);
  for (int j = starts.first(); j < majorLength - first; ++j) {
    starts.start(j, backward, opposite.far, s);
    if (!backward.anyLineOnGrid(j)) continue;
    const int k = majorLength - 1 - j;
    const auto [lo, hi] = k < visitEnd ? texelsAt(k) : std::pair{1, 0};
    backward.step(j, lo, hi, s.opposite.data() + static_cast<size_t>(k) * HorizonBlock::kLines);
  }
  return {first, last};
}

// Both azimuths at once: lines of `sweep` in groups as in sweepBlocks, and
// for each group the lines of `opposite` (the sweep of -u) that pass beside
// the same texels, walked first, their tangents kept per step. Groups of
// groupLines (<= kLines) lines: the opposite walk of a group walks
// groupLines + 1 lines plus the spread of the opposite lines' offsets
// against the group's (oppositeLines()).
template <bool kMajorIsColumn>
void sweepOpposedBlocks(const BlockSweep& sweep, const BlockSweep& opposite, int groupLines,
                        const HorizonBlockVisitor& visit) {
  forEachGroup<kMajorIsColumn>(sweep, groupLines, [&](const auto& texels, BlockScratch& s) {
    const auto texelsAt = [&](int step) { return texels.at(step); };
    const auto [first, last] =
        walkOpposite<kMajorIsColumn>(opposite, 0, sweep.layout.majorLength, texelsAt, s);
    if (first > last) return;
    walkGroup(sweep, texels, s, last + 1, texelsAt,
              [&](int step, int, int, const float* tanHorizon, const BlockSlopes& slopes) {
                HorizonBlock block = texels.block(step, tanHorizon, slopes);
                block.tanOpposite =
                    s.opposite.data() + static_cast<size_t>(step) * HorizonBlock::kLines;
                visit(block);
              });
  });
}

// sweepOpposedBlocks for a partial window (sweepWindowBlocks): for each
// group the opposite lines beside its window texels are walked first, each
// from its start in the opposite layout (the near reach beyond the first
// window texel it passes beside) with its own far samples, their tangents
// kept per step; then the group's lines, and each block carries both.
template <bool kMajorIsColumn>
void sweepOpposedWindowBlocks(const BlockSweep& sweep, const BlockSweep& opposite, int groupLines,
                              const HorizonBlockVisitor& visit) {
  const SweepLayout& layout = sweep.layout;
  forEachGroup<kMajorIsColumn>(sweep, groupLines, [&](const auto& texels, BlockScratch& s) {
    const WindowTexels<kMajorIsColumn> window{layout, texels};
    const auto texelsAt = [&](int step) { return window.at(step); };
    const auto [first, last] =
        walkOpposite<kMajorIsColumn>(opposite, layout.visitStep, layout.endStep, texelsAt, s);
    if (first > last) return;  // no texel of the window
    walkGroup(sweep, texels, s, last + 1, texelsAt,
              [&](int step, int lo, int hi, const float* tanHorizon, const BlockSlopes& slopes) {
                HorizonBlock b = windowBlock(sweep, window, step, lo, hi, tanHorizon, slopes);
                b.tanOpposite =
                    s.opposite.data() + static_cast<size_t>(step) * HorizonBlock::kLines;
                visit(b);
              });
  });
}

// Lines the opposite walk of sweepOpposedBlocks needs per group at most:
// the group's texels' spread of offsets between the two layouts, plus the
// group's lines and the one before. 0 when the layouts do not pair (the
// lines advance along different axes).
int oppositeLines(const SweepLayout& layout, const SweepLayout& opposite) {
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

// sweepReachM, for a block sweep: a limit it does not scan is refused.
double sweepReach(const BakeTerrain& terrain, const HorizonSweepOptions& options) {
  if (options.maxDistanceM > 0.0 && !scansWithinLimit(terrain, options)) {
    throw std::invalid_argument(
        "the block sweeps take only a distance limit they scan (scansWithinLimit)");
  }
  return sweepReachM(options);
}

}  // namespace

bool horizonAvx2() {
#if AAL_HORIZON_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2 && horizonAvx2Allowed.load(std::memory_order_relaxed);
#else
  return false;
#endif
}

}  // namespace detail

int windowSweepHalo(const BakeTerrain& terrain, double reachM) {
  return detail::stepsCovering(terrain, reachM) + detail::BlockLineWalker<true>::kMaxLines + 3;
}

void setHorizonAvx2Allowed(bool allowed) {
  detail::horizonAvx2Allowed.store(allowed, std::memory_order_relaxed);
}

void sweepHorizonBlocks(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& options,
                        HorizonBlockVisitor visit) {
  // A limit's lines start where they first come within it of a texel.
  if (options.maxDistanceM > 0.0) return sweepWindowHorizonBlocks(terrain, phi, options, visit);
  const double ux = std::cos(phi), uy = std::sin(phi);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy);
  const detail::BlockSweep sweep{terrain, layout, ux, uy, options};
  if (layout.majorIsColumn) {
    detail::sweepBlocks<true>(sweep, visit);
  } else {
    detail::sweepBlocks<false>(sweep, visit);
  }
}

void sweepWindowHorizonBlocks(const BakeTerrain& terrain, double phi,
                              const HorizonSweepOptions& options, HorizonBlockVisitor visit,
                              const FarFieldWindow* far) {
  const double reach = detail::sweepReach(terrain, options);
  if (options.clampEdge && !far && options.maxDistanceM <= 0.0) {
    throw std::invalid_argument("sweepWindowHorizonBlocks: clamped edges need the far field");
  }
  const double ux = std::cos(phi), uy = std::sin(phi);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy, reach);
  std::optional<FarLineMarch> farMarch;
  if (far) farMarch.emplace(*far, terrain, phi);
  const detail::BlockSweep sweep{terrain, layout, ux, uy, options, farMarch ? &*farMarch : nullptr};
  if (layout.majorIsColumn) {
    detail::sweepWindowBlocks<true>(sweep, visit);
  } else {
    detail::sweepWindowBlocks<false>(sweep, visit);
  }
}

bool sweepOpposedHorizonBlocks(const BakeTerrain& terrain, double phi, double phiOpposite,
                               const HorizonSweepOptions& options, HorizonBlockVisitor visit,
                               const FarFieldWindow* far) {
  const double reach = detail::sweepReach(terrain, options);
  const bool window = reach > 0.0;
  if (options.clampEdge && window && !far && options.maxDistanceM <= 0.0) {
    throw std::invalid_argument("sweepOpposedHorizonBlocks: clamped edges need the far field");
  }
  const double ux = std::cos(phi), uy = std::sin(phi);
  const double oppositeUx = std::cos(phiOpposite), oppositeUy = std::sin(phiOpposite);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy, reach);
  const detail::SweepLayout oppositeLayout =
      detail::makeSweepLayout(terrain, oppositeUx, oppositeUy, reach);
  const int lines = detail::oppositeLines(layout, oppositeLayout);
  if (lines < 1 || lines > detail::BlockLineWalker<true>::kMaxLines) return false;
  // Where oblique lines spread (lines > kLines + 1), smaller groups keep the
  // opposite walk at kLines + 1 lines: 5 vectors of 8 rather than 6.
  const int groupLines = HorizonBlock::kLines - (lines - (HorizonBlock::kLines + 1));
  std::optional<FarLineMarch> farMarch, oppositeFarMarch;
  if (window && far) {
    farMarch.emplace(*far, terrain, phi);
    oppositeFarMarch.emplace(*far, terrain, phiOpposite);
  }
  const detail::BlockSweep sweep{terrain, layout, ux, uy, options, farMarch ? &*farMarch : nullptr};
  const detail::BlockSweep opposite{terrain,    oppositeLayout,
                                    oppositeUx, oppositeUy,
                                    options,    oppositeFarMarch ? &*oppositeFarMarch : nullptr};
  if (window) {
    if (layout.majorIsColumn) {
      detail::sweepOpposedWindowBlocks<true>(sweep, opposite, groupLines, visit);
    } else {
      detail::sweepOpposedWindowBlocks<false>(sweep, opposite, groupLines, visit);
    }
  } else if (layout.majorIsColumn) {
    detail::sweepOpposedBlocks<true>(sweep, opposite, groupLines, visit);
  } else {
    detail::sweepOpposedBlocks<false>(sweep, opposite, groupLines, visit);
  }
  return true;
}

}  // namespace aal
