// The line sweep of horizon_sweep.h, restructured for speed: the same lines,
// hulls and blending, but each step of a group of lines hands the horizons
// of its texels over as one block, and the arithmetic runs in single
// precision in loops over the group that the compiler turns into vector
// code. The hull update (a stack pop loop per line) is scalar, except on
// CPUs with AVX2, where it runs 8 lines at a time (BlockLineWalker::walkAvx2,
// chosen at run time; the same results bit for bit).
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
#include <atomic>
#include <cmath>
#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#define AAL_HORIZON_AVX2 1
#else
#define AAL_HORIZON_AVX2 0
#endif

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
  // 39 beat 32 by 3 % at 1024² and 2.5 % at 4096² with the AVX2 walk: its
  // group walks 40 lines, 5 whole vectors of 8, where 32 walks 33.
  static constexpr int kLines = 39;
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
  // The surface's slopes at the texels, BakeTerrain::slopeEastAt and
  // slopeNorthAt bit for bit: the walk computes them from the heights it
  // loads anyway, so a bake needs no stored slopes.
  const float* slopeEast = nullptr;
  const float* slopeNorth = nullptr;
  // Room for a block's texels in whole vectors of 8.
  static constexpr int kPaddedTexels = (kLines + 7) / 8 * 8;
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

// setHorizonAvx2Allowed(): off, the scalar paths run even where AVX2 would.
inline std::atomic<bool> horizonAvx2Allowed{true};

// Whether this CPU runs the AVX2 hull update (BlockLineWalker) and the
// bake's AVX2 visitor: the build targets plain x86-64, so the choice is
// made at run time.
inline bool horizonAvx2() {
#if AAL_HORIZON_AVX2
  static const bool avx2 = __builtin_cpu_supports("avx2");
  return avx2 && horizonAvx2Allowed.load(std::memory_order_relaxed);
#else
  return false;
#endif
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
        rowCentre_(0.5f * static_cast<float>(terrain.height - 1)),
        avx2_(horizonAvx2()) {
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
    std::fill(size_, size_ + kPaddedLines, 0);
    // Read (and ignored) in lanes without a hull yet.
    for (float* a : {edgeT_, edgeZ_, topT_, topZ_, belowT_, belowZ_, thirdT_, thirdZ_}) {
      std::fill(a, a + kPaddedLines, 0.0f);
    }
  }

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
            float* north = nullptr) {
#if AAL_HORIZON_AVX2
    if (avx2_) return stepAvx2(step, minorLo, minorHi, out, east, north);
#endif
    stepImpl<false>(step, minorLo, minorHi, out, east, north);
  }

 private:
  // Per-line arrays run to whole vectors of 8 lines.
  static constexpr int kPaddedLines = (kMaxLines + 7) / 8 * 8;

  // The body of step(); kAvx2: compiled for AVX2 (stepAvx2), with the line
  // samples, hull updates and texels 4 or 8 lines at a time
  // (lineSamplesAvx2, walkAvx2).
  template <bool kAvx2>
  [[gnu::always_inline]] inline void stepImpl(int step, int minorLo, int minorHi, float* out,
                                              float* east, float* north);
#if AAL_HORIZON_AVX2
  __attribute__((target("avx2"))) void stepAvx2(int step, int minorLo, int minorHi, float* out,
                                                float* east, float* north) {
    stepImpl<true>(step, minorLo, minorHi, out, east, north);
  }
#endif
  // What stepImpl gathers per step before the hull updates, for walkAvx2.
  struct StepSlice {
    int base, lineFirst, lineLast;
    float w;
    bool offGridMajor;
    const float *heights, *nextSlice, *invCellX, *lineT;
    // The slopes' neighbours: the slices at major - 1 and major + 1
    // (heights where off the grid) and their difference's scale.
    const float *majorLow, *majorHigh;
    float majorScale;
    float *east, *north;  // null: no slopes wanted
  };
#if AAL_HORIZON_AVX2
  __attribute__((target("avx2"))) void lineSamplesAvx2(int step, int major, float* lineT,
                                                       int& lineFirst, int& lineLast) const;
  __attribute__((target("avx2"))) void walkAvx2(const StepSlice& slice, int minorLo, int minorHi,
                                                float* out);
#endif

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
  const bool avx2_;
  int dMajorNeighbour_, dMinorNeighbour_;
  float wMajorNeighbour_, wMinorNeighbour_, invCellY_;
  int firstLine_ = 0, lines_ = 0;
  // Per walked line: hull size (0: not started) and the DEM edge ahead.
  alignas(32) int size_[kPaddedLines];
  alignas(32) float edgeT_[kPaddedLines], edgeZ_[kPaddedLines];
  // The AVX2 path's copy of the top three hull points, hull[size - 1],
  // hull[size - 2] and hull[size - 3]: the first two pop tests of a step
  // need no gather (4 % faster than two at 1024²; most lines pop once).
  alignas(32) float topT_[kPaddedLines], topZ_[kPaddedLines];
  alignas(32) float belowT_[kPaddedLines], belowZ_[kPaddedLines];
  alignas(32) float thirdT_[kPaddedLines], thirdZ_[kPaddedLines];
};

template <bool kMajorIsColumn>
template <bool kAvx2>
inline void BlockLineWalker<kMajorIsColumn>::stepImpl(int step, int minorLo, int minorHi,
                                                      float* out, float* east, float* north) {
  constexpr int kMax = kPaddedLines;
  const int lines = lines_, majorLength = layout_.majorLength, minorMax = minorMax_;
  const float curvature = curvature_;
  const int major = layout_.start + step * layout_.step;
  // Walked line i passes between texels base + i and base + i + 1: the
  // texels between walked lines are base + 1 .. base + lines - 1.
  const int base = firstLine_ + layout_.floorOffset[step];
  const float w = static_cast<float>(layout_.fraction[step]);

  // Per step, index j of these holds minor coordinate base - 1 + j.
  float heights[kMax + 2], nextSlice[kMax + 2], backSlice[kMax + 2], invCellX[kMax + 2];
  float lineT[kMax], lineZ[kMax], lineCurvedZ[kMax];
  float riseToNear[kMax], runToNear[kMax], lineHorizon[kMax];

  // Heights around the lines on this slice and, for the leaving slope, on
  // the next one (clamped to the grid; what lies off it is masked).
  const int nextMajor = major + dMajorNeighbour_;
  const bool haveNextSlice = nextMajor >= 0 && nextMajor < majorLength;
  // The cell ahead is off the grid: no leaving slope (LineWalker::leavingSlope).
  const bool offGridMajor = wMajorNeighbour_ > 0.0f && !haveNextSlice;
  // For the slopes, the slice behind too: the previous step's, in cache.
  const int backMajor = major - dMajorNeighbour_;
  const bool haveBackSlice = east && backMajor >= 0 && backMajor < majorLength;
  // The heights of steps ahead, a row or a column that the hardware
  // prefetcher does not foresee (the previous step's are on the next
  // slice): 6 % faster at 4096², the same at 1024² (in cache anyway).
  if constexpr (kMajorIsColumn) {
    // A cache line holds 16 columns: every 8 steps, the column 16 on.
    const int ahead = step + 16;
    if ((step & 7) == 0 && ahead < majorLength) {
      const int aheadMajor = layout_.start + ahead * layout_.step;
      const int aheadBase = firstLine_ + layout_.floorOffset[ahead];
      for (int j = std::max(aheadBase - 1, 0); j <= std::min(aheadBase + lines, minorMax); ++j) {
        __builtin_prefetch(&field_.z[field_.index(aheadMajor, j)]);
      }
    }
  } else {
    const int ahead = step + 2;
    if (ahead < majorLength) {
      const int aheadMajor = layout_.start + ahead * layout_.step;
      const int aheadBase = firstLine_ + layout_.floorOffset[ahead];
      const int lo = std::max(aheadBase - 1, 0), hi = std::min(aheadBase + lines, minorMax);
      const float* row = &field_.z[field_.index(0, aheadMajor)];
      for (int j = lo; j < hi; j += 16) __builtin_prefetch(row + j);
      if (lo <= hi) __builtin_prefetch(row + hi);
    }
  }
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
  const float* majorLow = dMajorNeighbour_ > 0 ? behind : ahead;
  const float* majorHigh = dMajorNeighbour_ > 0 ? ahead : behind;
  const float majorScale =
      BakeTerrain::differenceScale(std::max(major - 1, 0), std::min(major + 1, majorLength - 1));

  // Line samples: distance along u and height, linear across the line.
  int lineFirst = lines, lineLast = -1;
#if AAL_HORIZON_AVX2
  if constexpr (kAvx2) lineSamplesAvx2(step, major, lineT, lineFirst, lineLast);
#endif
  for (int i = 0; i < lines && !kAvx2; ++i) {
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
#if AAL_HORIZON_AVX2
  if constexpr (kAvx2) {
    walkAvx2({base, lineFirst, lineLast, w, offGridMajor, heights, nextSlice, invCellX, lineT,
              majorLow, majorHigh, majorScale, east, north},
             minorLo, minorHi, out);
    return;
  }
#endif
  for (int i = lineFirst; i <= lineLast; ++i) {
    lineZ[i] = (1.0f - w) * heights[i + 1] + w * heights[i + 2];
    lineCurvedZ[i] = lineZ[i] - curvature * lineT[i] * lineT[i];
  }

  // Hull update, line by line: pop what falls under the new point, and the
  // point left behind it is the tangent point of its horizon.
  for (int i = lineFirst; i <= lineLast; ++i) {
    HullPointF* hull = hulls_ + static_cast<size_t>(i) * majorLength;
    const float t = lineT[i], z = lineCurvedZ[i];
    if (size_[i] == 0) {
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
    if (!east) continue;
    // The slopes, as BakeTerrain::slopeEastAt and slopeNorthAt compute them.
    const int minor = base + i;
    const float minorScale =
        BakeTerrain::differenceScale(std::max(minor - 1, 0), std::min(minor + 1, minorMax));
    if constexpr (kMajorIsColumn) {  // major: column, minor: row
      east[i - texelFirst] = (majorHigh[i + 1] - majorLow[i + 1]) * (majorScale * invCellX[i + 1]);
      north[i - texelFirst] = (heights[i] - heights[i + 2]) * (minorScale * invCellY_);
    } else {  // major: row, minor: column
      east[i - texelFirst] = (heights[i + 2] - heights[i]) * (minorScale * invCellX[i + 1]);
      north[i - texelFirst] = (majorLow[i + 1] - majorHigh[i + 1]) * (majorScale * invCellY_);
    }
  }
}

#if AAL_HORIZON_AVX2
// clampedEdgeSlopeF in 8 lanes.
__attribute__((target("avx2"))) inline __m256 clampedEdgeSlopeAvx2(__m256 rise, __m256 toEdge,
                                                                   float curvature) {
  const __m256 zero = _mm256_setzero_ps(), noHorizon = _mm256_set1_ps(kNoHorizonTangent);
  const __m256 drop = _mm256_sub_ps(zero, rise);
  const __m256 tangentDistance = _mm256_sqrt_ps(
      _mm256_div_ps(_mm256_max_ps(drop, zero), _mm256_set1_ps(std::max(curvature, 1e-30f))));
  const __m256 curved = _mm256_blendv_ps(
      _mm256_mul_ps(_mm256_set1_ps(-2.0f),
                    _mm256_sqrt_ps(_mm256_mul_ps(drop, _mm256_set1_ps(curvature)))),
      noHorizon, _mm256_cmp_ps(tangentDistance, toEdge, _CMP_LE_OQ));
  const __m256 beyond = _mm256_blendv_ps(curvature <= 0.0f ? zero : curved, noHorizon,
                                         _mm256_cmp_ps(rise, zero, _CMP_GE_OQ));
  return _mm256_blendv_ps(beyond, zero, _mm256_cmp_ps(toEdge, zero, _CMP_LE_OQ));
}

// a[start .. start + 7] as a vector, from aligned loads (a runs to whole
// vectors past start + 7).
__attribute__((target("avx2"))) inline __m256 shiftedLanesAvx2(const float* a, int start) {
  const float* at = a + (start & ~7);
  const __m256i index =
      _mm256_add_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(start & 7));
  const __m256 low = _mm256_permutevar8x32_ps(_mm256_load_ps(at), index);
  const __m256 high = _mm256_permutevar8x32_ps(_mm256_load_ps(at + 8), index);
  return _mm256_blendv_ps(low, high,
                          _mm256_castsi256_ps(_mm256_cmpgt_epi32(index, _mm256_set1_epi32(7))));
}

// The line samples' distances along u, 4 lines at a time in double
// precision: the same operations as the scalar loop.
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::lineSamplesAvx2(
    int step, int major, float* lineT, int& lineFirst, int& lineLast) const {
  const int minorMax = minorMax_;
  const __m256d lowest = _mm256_setzero_pd(), highest = _mm256_set1_pd(minorMax);
  const __m256d centreCol = _mm256_set1_pd(terrain_.centreCol);
  const __m256d ux = _mm256_set1_pd(ux_), uy = _mm256_set1_pd(uy_);
  const __m256d iota = _mm256_setr_pd(0, 1, 2, 3);
  unsigned long long validBits = 0;
  for (int i = 0; i < lines_; i += 4) {
    // (firstLine + i) + step * minorPerStep, as the scalar loop rounds it.
    const __m256d minor =
        _mm256_add_pd(_mm256_add_pd(_mm256_set1_pd(static_cast<double>(firstLine_ + i)), iota),
                      _mm256_set1_pd(step * layout_.minorPerStep));
    const __m256d inside = _mm256_and_pd(_mm256_cmp_pd(minor, lowest, _CMP_GE_OQ),
                                         _mm256_cmp_pd(minor, highest, _CMP_LE_OQ));
    validBits |= static_cast<unsigned long long>(_mm256_movemask_pd(inside)) << i;
    __m256d t;
    if constexpr (kMajorIsColumn) {
      const __m128i nearRow = _mm_min_epi32(
          _mm256_cvttpd_epi32(_mm256_add_pd(_mm256_max_pd(minor, lowest), _mm256_set1_pd(0.5))),
          _mm_set1_epi32(minorMax));
      // A gather only where rows differ: at 16384² a tenth of the column
      // walk's step samples fell just after it.
      const __m256d cellX =
          terrain_.uniformCellX
              ? _mm256_set1_pd(terrain_.rowCellX[0])
              : _mm256_mask_i32gather_pd(_mm256_setzero_pd(), terrain_.rowCellX.data(), nearRow,
                                         _mm256_castsi256_pd(_mm256_set1_epi64x(-1)), 8);
      t = _mm256_add_pd(
          _mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(major - terrain_.centreCol), cellX), ux),
          _mm256_mul_pd(_mm256_mul_pd(_mm256_sub_pd(_mm256_set1_pd(rowCentre_), minor),
                                      _mm256_set1_pd(terrain_.cellY)),
                        uy));
    } else {
      t = _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_sub_pd(minor, centreCol),
                                                    _mm256_set1_pd(terrain_.rowCellX[major])),
                                      ux),
                        _mm256_set1_pd(terrain_.y(major) * uy_));
    }
    _mm_storeu_ps(lineT + i, _mm256_cvtpd_ps(t));
  }
  validBits &= lines_ >= 64 ? ~0ull : (1ull << lines_) - 1;
  if (validBits) {
    lineFirst = __builtin_ctzll(validBits);
    lineLast = 63 - __builtin_clzll(validBits);
  }
}

// The rest of step() for AVX2, in lanes of 8 lines: each round of pops
// tests all lanes at once and gathers the next point down only for the
// lanes that popped, until no lane pops; the texels then take their two
// lines' tangents by lane shifts in registers (shifted loads of what was
// just stored would stall on store forwarding). Bit for bit the scalar
// path's result: the same operations in the same order, no fused
// multiply-adds (the walk targets AVX2 without FMA: GCC fuses the
// intrinsics' multiplies and adds too where FMA is enabled).
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::walkAvx2(
    const StepSlice& slice, int minorLo, int minorHi, float* out) {
  const int majorLength = layout_.majorLength, lines = lines_;
  const bool texels = minorLo <= minorHi;
  alignas(32) float lineCurvedZ[kPaddedLines], lineHorizon[kPaddedLines + 8];
  const __m256 noHorizon = _mm256_set1_ps(kNoHorizonTangent);
  const __m256 w = _mm256_set1_ps(slice.w), w1 = _mm256_set1_ps(1.0f - slice.w);
  const __m256 curvature = _mm256_set1_ps(curvature_);
  const __m256 twoCurvature = _mm256_set1_ps(2.0f * curvature_);
  const long long* points = reinterpret_cast<const long long*>(hulls_);
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i one = _mm256_set1_epi32(1);
  // A gather of 4 points (t, z pairs) per half: lanes 0, 1, 4, 5 and 2, 3,
  // 6, 7, so that one shuffle per coordinate puts the 8 back in order.
  const __m256i indexLow = _mm256_setr_epi32(0, 1, 4, 5, 0, 0, 0, 0);
  const __m256i indexHigh = _mm256_setr_epi32(2, 3, 6, 7, 0, 0, 0, 0);
  const __m256i maskLow = _mm256_setr_epi32(0, 0, 1, 1, 4, 4, 5, 5);
  const __m256i maskHigh = _mm256_setr_epi32(2, 2, 3, 3, 6, 6, 7, 7);
  for (int c = 0; c < lines; c += 8) {
    const __m256i line = _mm256_add_epi32(_mm256_set1_epi32(c), iota);
    const __m256i valid =
        _mm256_and_si256(_mm256_cmpgt_epi32(line, _mm256_set1_epi32(slice.lineFirst - 1)),
                         _mm256_cmpgt_epi32(_mm256_set1_epi32(slice.lineLast + 1), line));
    if (_mm256_testz_si256(valid, valid)) {
      _mm256_store_ps(lineHorizon + c, noHorizon);
      continue;
    }
    const __m256 t = _mm256_loadu_ps(slice.lineT + c);
    const __m256 z = _mm256_add_ps(_mm256_mul_ps(w1, _mm256_loadu_ps(slice.heights + c + 1)),
                                   _mm256_mul_ps(w, _mm256_loadu_ps(slice.heights + c + 2)));
    const __m256 curvedZ = _mm256_sub_ps(z, _mm256_mul_ps(_mm256_mul_ps(curvature, t), t));
    _mm256_store_ps(lineCurvedZ + c, curvedZ);
    __m256i n = _mm256_load_si256(reinterpret_cast<const __m256i*>(size_ + c));
    const __m256 fresh =
        _mm256_castsi256_ps(_mm256_and_si256(valid, _mm256_cmpeq_epi32(n, _mm256_setzero_si256())));
    const __m256 edgeT = _mm256_blendv_ps(_mm256_load_ps(edgeT_ + c), t, fresh);
    const __m256 edgeZ = _mm256_blendv_ps(_mm256_load_ps(edgeZ_ + c), z, fresh);
    _mm256_store_ps(edgeT_ + c, edgeT);
    _mm256_store_ps(edgeZ_ + c, edgeZ);

    // Pop: a is hull[n - 1], b hull[n - 2]. A lane that pops in round k
    // takes hull[n0 - 3 - k] for b, whatever the other lanes did: in round
    // 0 the cached third point, later a gather issued before the round's
    // test, off the tests' dependency chain (clamped to the line's own
    // points; what lanes that stopped read is not used).
    __m256 aT = _mm256_load_ps(topT_ + c), aZ = _mm256_load_ps(topZ_ + c);
    __m256 bT = _mm256_load_ps(belowT_ + c), bZ = _mm256_load_ps(belowZ_ + c);
    __m256 nextT = _mm256_load_ps(thirdT_ + c), nextZ = _mm256_load_ps(thirdZ_ + c);
    const __m256i first = _mm256_mullo_epi32(line, _mm256_set1_epi32(majorLength));
    const __m256i next = _mm256_add_epi32(first, _mm256_sub_epi32(n, _mm256_set1_epi32(4)));
    const __m128i firstLow = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(first, indexLow));
    const __m128i firstHigh = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(first, indexHigh));
    __m128i nextLow = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(next, indexLow));
    __m128i nextHigh = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(next, indexHigh));
    const __m256i gatherLow = _mm256_permutevar8x32_epi32(valid, maskLow);
    const __m256i gatherHigh = _mm256_permutevar8x32_epi32(valid, maskHigh);
    __m256i active = _mm256_and_si256(valid, _mm256_cmpgt_epi32(n, one));
    for (bool gathered = false;; gathered = true) {
      if (gathered) {
        const __m256 low = _mm256_castsi256_ps(_mm256_mask_i32gather_epi64(
            _mm256_setzero_si256(), points, _mm_max_epi32(nextLow, firstLow), gatherLow, 8));
        const __m256 high = _mm256_castsi256_ps(_mm256_mask_i32gather_epi64(
            _mm256_setzero_si256(), points, _mm_max_epi32(nextHigh, firstHigh), gatherHigh, 8));
        nextLow = _mm_sub_epi32(nextLow, _mm_set1_epi32(1));
        nextHigh = _mm_sub_epi32(nextHigh, _mm_set1_epi32(1));
        nextT = _mm256_shuffle_ps(low, high, _MM_SHUFFLE(2, 0, 2, 0));
        nextZ = _mm256_shuffle_ps(low, high, _MM_SHUFFLE(3, 1, 3, 1));
      }
      const __m256 under = _mm256_cmp_ps(
          _mm256_mul_ps(_mm256_sub_ps(bZ, curvedZ), _mm256_sub_ps(aT, t)),
          _mm256_mul_ps(_mm256_sub_ps(aZ, curvedZ), _mm256_sub_ps(bT, t)), _CMP_GE_OQ);
      const __m256i pop = _mm256_and_si256(active, _mm256_castps_si256(under));
      if (_mm256_testz_si256(pop, pop)) break;
      n = _mm256_add_epi32(n, pop);  // -1 where popped
      aT = _mm256_blendv_ps(aT, bT, _mm256_castsi256_ps(pop));
      aZ = _mm256_blendv_ps(aZ, bZ, _mm256_castsi256_ps(pop));
      bT = _mm256_blendv_ps(bT, nextT, _mm256_castsi256_ps(pop));
      bZ = _mm256_blendv_ps(bZ, nextZ, _mm256_castsi256_ps(pop));
      active = _mm256_and_si256(pop, _mm256_cmpgt_epi32(n, one));
    }
    // The new point goes on top (pushed below), a below it, b below that.
    const __m256 keep = _mm256_castsi256_ps(valid);
    _mm256_store_ps(thirdT_ + c, _mm256_blendv_ps(_mm256_load_ps(thirdT_ + c), bT, keep));
    _mm256_store_ps(thirdZ_ + c, _mm256_blendv_ps(_mm256_load_ps(thirdZ_ + c), bZ, keep));
    _mm256_store_ps(belowT_ + c, _mm256_blendv_ps(_mm256_load_ps(belowT_ + c), aT, keep));
    _mm256_store_ps(belowZ_ + c, _mm256_blendv_ps(_mm256_load_ps(belowZ_ + c), aZ, keep));
    _mm256_store_ps(topT_ + c, _mm256_blendv_ps(_mm256_load_ps(topT_ + c), t, keep));
    _mm256_store_ps(topZ_ + c, _mm256_blendv_ps(_mm256_load_ps(topZ_ + c), curvedZ, keep));
    _mm256_store_si256(
        reinterpret_cast<__m256i*>(size_ + c),
        _mm256_blendv_epi8(_mm256_load_si256(reinterpret_cast<const __m256i*>(size_ + c)),
                           _mm256_add_epi32(n, one), valid));
    if (!texels) continue;

    // The tangent from the new point to a; none where nothing lies ahead.
    const __m256 ahead = _mm256_castsi256_ps(_mm256_cmpgt_epi32(n, _mm256_setzero_si256()));
    const __m256 slope =
        _mm256_div_ps(_mm256_blendv_ps(noHorizon, _mm256_sub_ps(aZ, curvedZ), ahead),
                      _mm256_blendv_ps(_mm256_set1_ps(1.0f), _mm256_sub_ps(aT, t), ahead));
    __m256 horizon = _mm256_blendv_ps(_mm256_add_ps(slope, _mm256_mul_ps(twoCurvature, t)),
                                      noHorizon, _mm256_cmp_ps(slope, noHorizon, _CMP_LE_OQ));
    if (clampEdge_) {
      horizon = _mm256_max_ps(
          clampedEdgeSlopeAvx2(_mm256_sub_ps(edgeZ, z), _mm256_sub_ps(edgeT, t), curvature_),
          horizon);
    }
    _mm256_store_ps(lineHorizon + c, _mm256_blendv_ps(noHorizon, horizon, keep));
  }
  for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
    hulls_[static_cast<size_t>(i) * majorLength + size_[i] - 1] = {slice.lineT[i], lineCurvedZ[i]};
  }
  if (!texels) return;

  // The texels: texel j lies between lines j + texelFirst - 1 and j +
  // texelFirst.
  const int texelFirst = minorLo - slice.base, count = minorHi - minorLo + 1;
  const __m256 invCellY = _mm256_set1_ps(invCellY_);
  const __m256 wMajor = _mm256_set1_ps(wMajorNeighbour_), wMinor = _mm256_set1_ps(wMinorNeighbour_);
  const bool wZero = slice.w == 0.0f, minorChecked = wMinorNeighbour_ > 0.0f;
  for (int j = 0; j < count; j += 8) {
    const int i = j + texelFirst;  // first texel's line; heights index i + 1
    const __m256 nearLine = shiftedLanesAvx2(lineHorizon, i),
                 farLine = shiftedLanesAvx2(lineHorizon, i - 1);
    const __m256 blended =
        _mm256_add_ps(nearLine, _mm256_mul_ps(w, _mm256_sub_ps(farLine, nearLine)));
    const __m256 nearNone = _mm256_cmp_ps(nearLine, noHorizon, _CMP_LE_OQ);
    const __m256 farNone = _mm256_cmp_ps(farLine, noHorizon, _CMP_LE_OQ);
    const __m256 blend =
        wZero ? nearLine
              : _mm256_blendv_ps(_mm256_blendv_ps(blended, farLine, nearNone), nearLine, farNone);
    const __m256 own = _mm256_loadu_ps(slice.heights + i + 1);
    const __m256 invCellX = _mm256_loadu_ps(slice.invCellX + i + 1);
    const __m256 invCellMajor = kMajorIsColumn ? invCellX : invCellY;
    const __m256 invCellMinor = kMajorIsColumn ? invCellY : invCellX;
    const __m256 leaving = _mm256_add_ps(
        _mm256_mul_ps(
            _mm256_mul_ps(wMajor, _mm256_sub_ps(_mm256_loadu_ps(slice.nextSlice + i + 1), own)),
            invCellMajor),
        _mm256_mul_ps(_mm256_mul_ps(wMinor, _mm256_sub_ps(_mm256_loadu_ps(slice.heights + i + 1 +
                                                                          dMinorNeighbour_),
                                                          own)),
                      invCellMinor));
    __m256 offGrid = _mm256_castsi256_ps(_mm256_set1_epi32(slice.offGridMajor ? -1 : 0));
    if (minorChecked) {
      const __m256i minorNeighbour =
          _mm256_add_epi32(_mm256_set1_epi32(slice.base + i + dMinorNeighbour_), iota);
      offGrid = _mm256_or_ps(
          offGrid, _mm256_castsi256_ps(_mm256_or_si256(
                       _mm256_cmpgt_epi32(_mm256_setzero_si256(), minorNeighbour),
                       _mm256_cmpgt_epi32(minorNeighbour, _mm256_set1_epi32(minorMax_)))));
    }
    const __m256 result = _mm256_max_ps(_mm256_blendv_ps(leaving, noHorizon, offGrid), blend);
    if (j + 8 <= count) {
      _mm256_storeu_ps(out + j, result);
    } else {
      _mm256_maskstore_ps(out + j, _mm256_cmpgt_epi32(_mm256_set1_epi32(count - j), iota), result);
    }
    if (!slice.east) continue;
    // The slopes (the scalar loop's operations): the minor difference's
    // scale is 1/2 but at the grid's edges.
    const __m256i minor = _mm256_add_epi32(_mm256_set1_epi32(slice.base + i), iota);
    const __m256i span = _mm256_sub_epi32(
        _mm256_min_epi32(_mm256_add_epi32(minor, one), _mm256_set1_epi32(minorMax_)),
        _mm256_max_epi32(_mm256_sub_epi32(minor, one), _mm256_setzero_si256()));
    const __m256 minorScale = _mm256_blendv_ps(
        _mm256_and_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(span, one)), _mm256_set1_ps(1.0f)),
        _mm256_set1_ps(0.5f), _mm256_castsi256_ps(_mm256_cmpeq_epi32(span, _mm256_set1_epi32(2))));
    const __m256 minorLow = _mm256_loadu_ps(slice.heights + i);
    const __m256 minorHigh = _mm256_loadu_ps(slice.heights + i + 2);
    const __m256 majorLow = _mm256_loadu_ps(slice.majorLow + i + 1);
    const __m256 majorHigh = _mm256_loadu_ps(slice.majorHigh + i + 1);
    const __m256 majorScale = _mm256_set1_ps(slice.majorScale);
    if constexpr (kMajorIsColumn) {
      _mm256_storeu_ps(slice.east + j, _mm256_mul_ps(_mm256_sub_ps(majorHigh, majorLow),
                                                     _mm256_mul_ps(majorScale, invCellX)));
      _mm256_storeu_ps(slice.north + j, _mm256_mul_ps(_mm256_sub_ps(minorLow, minorHigh),
                                                      _mm256_mul_ps(minorScale, invCellY)));
    } else {
      _mm256_storeu_ps(slice.east + j, _mm256_mul_ps(_mm256_sub_ps(minorHigh, minorLow),
                                                     _mm256_mul_ps(minorScale, invCellX)));
      _mm256_storeu_ps(slice.north + j, _mm256_mul_ps(_mm256_sub_ps(majorLow, majorHigh),
                                                      _mm256_mul_ps(majorScale, invCellY)));
    }
  }
}
#endif

// A step's slopes (HorizonBlock::slopeEast, slopeNorth), zeroed once so
// that the vector loops never meet stale lanes.
struct BlockSlopes {
  alignas(32) float east[HorizonBlock::kPaddedTexels] = {};
  alignas(32) float north[HorizonBlock::kPaddedTexels] = {};
};

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
  HorizonBlock block(int step, const float* tanHorizon, const BlockSlopes& slopes) const {
    const auto [lo, hi] = at(step);
    HorizonBlock b;
    b.firstTexel = texel(step, lo);
    b.stride = kMajorIsColumn ? width : 1;
    b.count = hi - lo + 1;
    b.tanHorizon = tanHorizon;
    b.slopeEast = slopes.east;
    b.slopeNorth = slopes.north;
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
    BlockSlopes slopes;
    for (int step = 0; step < majorLength; ++step) {
      if (!walker.anyLineOnGrid(step)) continue;
      const auto [lo, hi] = texels.at(step);
      walker.step(step, lo, hi, tanHorizon, slopes.east, slopes.north);
      if (lo <= hi) visit(texels.block(step, tanHorizon, slopes));
    }
  });
}

// Both azimuths at once: lines of `layout` (u = (ux, uy)) in groups as in
// sweepBlocks, and for each group the lines of `opposite` (the layout of -u)
// that pass beside the same texels, walked first, their tangents kept per
// step. Groups of groupLines (<= kLines) lines: the opposite walk of a group
// walks groupLines + 1 lines plus the spread of the opposite lines' offsets
// against the group's (oppositeLines()).
template <bool kMajorIsColumn, class VisitBlock>
void sweepOpposedBlocks(const BakeTerrain& terrain, const SweepLayout& layout,
                        const SweepLayout& opposite, double ux, double uy, double oppositeUx,
                        double oppositeUy, const HorizonSweepOptions& options, int groupLines,
                        VisitBlock& visit) {
  constexpr int kLines = HorizonBlock::kLines;
  using Walker = BlockLineWalker<kMajorIsColumn>;
  const int majorLength = layout.majorLength;
  tbb::enumerable_thread_specific<BlockScratch> scratch;

  const int firstLine = layout.firstLine + 1;
  const int groups = (layout.lastLine - firstLine + groupLines) / groupLines;
  tbb::parallel_for(0, groups, [&](int group) {
    BlockScratch& s = scratch.local();
    s.hulls.resize(static_cast<size_t>(Walker::kMaxLines) * majorLength);
    s.opposite.resize(static_cast<size_t>(kLines) * majorLength);
    const int first = firstLine + group * groupLines;
    const GroupTexels<kMajorIsColumn> texels{layout, terrain.field->width, first,
                                             std::min(groupLines, layout.lastLine + 1 - first)};

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
      if (!backward.anyLineOnGrid(majorLength - 1 - k)) continue;
      const auto [lo, hi] = texels.at(k);
      backward.step(majorLength - 1 - k, lo, hi,
                    s.opposite.data() + static_cast<size_t>(k) * kLines);
    }

    Walker forward(terrain, layout, ux, uy, options, s.hulls.data());
    forward.begin(first - 1, texels.count + 1);
    float tanHorizon[kLines];
    BlockSlopes slopes;
    for (int step = 0; step < majorLength; ++step) {
      if (!forward.anyLineOnGrid(step)) continue;
      const auto [lo, hi] = texels.at(step);
      forward.step(step, lo, hi, tanHorizon, slopes.east, slopes.north);
      if (lo > hi) continue;
      HorizonBlock block = texels.block(step, tanHorizon, slopes);
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

// sweepBlocks for a partial window without a distance limit (the near
// sweep of a far-field bake, far_horizon.h): the window's lines walked from
// layout.firstStep (options.windowReachM before the window), blocks only of
// the window's texels, indexed as BakeTerrain::windowIndex. Open edges
// only: the walker takes a line's first point for the field's edge.
template <bool kMajorIsColumn, class VisitBlock>
void sweepWindowBlocks(const BakeTerrain& terrain, const SweepLayout& layout, double ux, double uy,
                       const HorizonSweepOptions& options, VisitBlock& visit) {
  constexpr int kLines = HorizonBlock::kLines;
  using Walker = BlockLineWalker<kMajorIsColumn>;
  tbb::enumerable_thread_specific<BlockScratch> scratch;
  const TexelWindow& window = terrain.window;
  const int firstLine = layout.firstLine + 1;
  const int groups = (layout.lastLine - firstLine + kLines) / kLines;
  tbb::parallel_for(0, groups, [&](int group) {
    BlockScratch& s = scratch.local();
    s.hulls.resize(static_cast<size_t>(Walker::kMaxLines) * layout.majorLength);
    const int first = firstLine + group * kLines;
    const GroupTexels<kMajorIsColumn> texels{layout, terrain.field->width, first,
                                             std::min(kLines, layout.lastLine + 1 - first)};
    Walker walker(terrain, layout, ux, uy, options, s.hulls.data());
    walker.begin(first - 1, texels.count + 1);
    float tanHorizon[kLines];
    BlockSlopes slopes;
    for (int step = layout.firstStep; step < layout.endStep; ++step) {
      if (!walker.anyLineOnGrid(step)) continue;
      auto [lo, hi] = texels.at(step);
      if (step < layout.visitStep) hi = lo - 1;  // only fills the hulls
      lo = std::max(lo, layout.minorBegin);
      hi = std::min(hi, layout.minorEnd - 1);
      walker.step(step, lo, hi, tanHorizon, slopes.east, slopes.north);
      if (lo > hi) continue;
      const int major = layout.start + step * layout.step;
      HorizonBlock b;
      b.firstTexel =
          kMajorIsColumn ? terrain.windowIndex(major, lo) : terrain.windowIndex(lo, major);
      b.stride = kMajorIsColumn ? window.width : 1;
      b.count = hi - lo + 1;
      b.tanHorizon = tanHorizon;
      b.slopeEast = slopes.east;
      b.slopeNorth = slopes.north;
      visit(b);
    }
  });
}

}  // namespace detail

// Lets sweeps and bakes started from now on use AVX2 where the CPU has it
// (the default), or not: for tests of the scalar path on any CPU. Both
// paths give the same tangents bit for bit.
inline void setHorizonAvx2Allowed(bool allowed) {
  detail::horizonAvx2Allowed.store(allowed, std::memory_order_relaxed);
}

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

// The texels of a partial window (terrain.window) for azimuth phi, its
// lines walked with the unlimited hull from options.windowReachM before it:
// sweepHorizons() with windowReachM, in blocks whose texels are window
// indices (BakeTerrain::windowIndex). Open edges only (options.clampEdge
// must be false): the walk of a line that begins inside the field would
// take its first point for the edge.
template <class VisitBlock>
void sweepWindowHorizonBlocks(const BakeTerrain& terrain, double phi,
                              const HorizonSweepOptions& options, VisitBlock&& visit) {
  const double ux = std::cos(phi), uy = std::sin(phi);
  const detail::SweepLayout layout = detail::makeSweepLayout(terrain, ux, uy, options.windowReachM);
  if (layout.majorIsColumn) {
    detail::sweepWindowBlocks<true>(terrain, layout, ux, uy, options, visit);
  } else {
    detail::sweepWindowBlocks<false>(terrain, layout, ux, uy, options, visit);
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
  // Where oblique lines spread (lines > kLines + 1), smaller groups keep the
  // opposite walk at kLines + 1 lines: 5 vectors of 8 rather than 6.
  const int groupLines = HorizonBlock::kLines - (lines - (HorizonBlock::kLines + 1));
  if (layout.majorIsColumn) {
    detail::sweepOpposedBlocks<true>(terrain, layout, opposite, ux, uy, oppositeUx, oppositeUy,
                                     options, groupLines, visit);
  } else {
    detail::sweepOpposedBlocks<false>(terrain, layout, opposite, ux, uy, oppositeUx, oppositeUy,
                                      options, groupLines, visit);
  }
  return true;
}

}  // namespace aal
