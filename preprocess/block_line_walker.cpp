// The block sweep's line walker: set-up, the choice of walk, and the
// scalar walk (the AVX2 walk: bake_avx2.cpp).
#include "aperture/preprocess/block_line_walker.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

namespace aal::detail {

template <bool kMajorIsColumn>
BlockLineWalker<kMajorIsColumn>::BlockLineWalker(const BakeTerrain& terrain,
                                                 const SweepLayout& layout, double ux, double uy,
                                                 const HorizonSweepOptions& options,
                                                 HullPointF* hulls, ScanRing* ring)
    : terrain_(terrain),
      layout_(layout),
      ux_(ux),
      uy_(uy),
      hulls_(hulls),
      curvature_(static_cast<float>(options.curvature)),
      clampEdge_(options.clampEdge),
      maxDistance_(options.maxDistanceM),
      scan_(scansWithinLimit(terrain, options)),
      minorMax_(layout.minorLength - 1),
      rowCentre_(0.5f * static_cast<float>(terrain.height - 1)),
      avx2_(horizonAvx2()),
      ring_(ring) {
  if (scan_ && !ring_) throw std::logic_error("BlockLineWalker: a scanned limit needs a ScanRing");
  if (scan_ && terrain.uniformCellX && layout.majorLength >= 2) {
    // Points walked earlier lie farther along u: one step back is this far
    // (steps 0 and 1; a single slice has no point behind another). The
    // points within the limit lie fewer than stepsCovering steps back.
    const double stepT =
        lineT(layout.start, 0.0) - lineT(layout.start + layout.step, layout.minorPerStep);
    uniformSteps_ = true;
    const int steps = std::min(kScanRing, stepsCovering(terrain, maxDistance_));
    for (int k = 1; k < steps; ++k) {
      const float distance = static_cast<float>(k * stepT);
      scanInverse_[k] = 1.0f / distance;
      scanDrop_[k] = curvature_ * distance;
    }
  }
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
  const TexelWindow& held = terrain.heights.texels;
  residentHeights_ = terrain.heights.z.data();
  rowStride_ = held.width;
  residentOffset_ = held.row * rowStride_ + held.col;
  const int columns[2] = {held.col, held.col + held.width - 1};
  const int rows[2] = {held.row, held.row + held.height - 1};
  std::copy(kMajorIsColumn ? columns : rows, (kMajorIsColumn ? columns : rows) + 2, residentMajor_);
  std::copy(kMajorIsColumn ? rows : columns, (kMajorIsColumn ? rows : columns) + 2, residentMinor_);
}

template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::begin(int firstLine, int lines) {
  firstLine_ = firstLine;
  lines_ = lines;
  std::fill(size_, size_ + kPaddedLines, 0);
  // Read (and ignored) in lanes without a hull yet.
  for (float* a : {edgeT_, edgeZ_, topT_, topZ_, belowT_, belowZ_, thirdT_, thirdZ_}) {
    std::fill(a, a + kPaddedLines, 0.0f);
  }
}

template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::restart(int i, int step, const FarLineMarch* far,
                                              std::vector<float>& distance,
                                              std::vector<float>& height) {
  // As begin() leaves a line, then the far samples.
  size_[i] = 0;
  for (float* a : {edgeT_, edgeZ_, topT_, topZ_, belowT_, belowZ_, thirdT_, thirdZ_}) a[i] = 0.0f;
  if (far) seedLine(i, *far, step, distance, height);
}

template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::seedLine(int i, const FarLineMarch& far, int step,
                                               std::vector<float>& distance,
                                               std::vector<float>& height) {
  const int majorLength = layout_.majorLength;
  const int major = layout_.start + step * layout_.step;
  // The walk pushes at most one point per step from here: the far field
  // keeps to the room left (its hull is far smaller in practice).
  const int room = majorLength - (layout_.endStep - step) - 1;
  const double minor = (firstLine_ + i) + step * layout_.minorPerStep;
  if (minor < 0.0 || minor > minorMax_) return;
  // The samples beyond the line's first point, at (column, row).
  const double t = lineT(major, minor);
  if constexpr (kMajorIsColumn) {
    far.march(major, minor, distance, height);
  } else {
    far.march(minor, major, distance, height);
  }
  HullPointF* hull = hulls_ + static_cast<size_t>(i) * hullStride(majorLength);
  int n = 0;
  const int count = std::min(static_cast<int>(distance.size()), std::max(room, 0));
  for (int k = count - 1; k >= 0; --k) {
    const float pointT = static_cast<float>(t + distance[k]);
    const float z = height[k] - curvature_ * pointT * pointT;
    while (n >= 2 && hullTopUnder(hull, n, pointT, z)) --n;
    hull[n++] = {pointT, z};
  }
  size_[i] = n;
  // Clamped edges: the ground goes on flat from the last sample in the
  // DEM (else, as for a line that starts at the edge, from the first
  // point walked).
  if (!distance.empty()) {
    edgeT_[i] = static_cast<float>(t + distance.back());
    edgeZ_[i] = height.back();
  }
  // The AVX2 walk's copies of the top three points.
  if (n >= 1) topT_[i] = hull[n - 1].t, topZ_[i] = hull[n - 1].z;
  if (n >= 2) belowT_[i] = hull[n - 2].t, belowZ_[i] = hull[n - 2].z;
  if (n >= 3) thirdT_[i] = hull[n - 3].t, thirdZ_[i] = hull[n - 3].z;
}

template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::step(int step, int minorLo, int minorHi, float* out,
                                           float* east, float* north) {
#if AAL_HORIZON_AVX2
  if (avx2_) return stepAvx2(step, minorLo, minorHi, out, east, north);
#endif
  stepScalar(step, minorLo, minorHi, out, east, north);
}

template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::stepScalar(int step, int minorLo, int minorHi, float* out,
                                                 float* east, float* north) {
  StepSlice slice;
  prefetchAhead(step);
  loadSlice<false>(step, east, north, slice);
  lineSamples(step, slice);
  LineValues lines;
  if (scan_) {
    alignas(32) float z[kPaddedLines] = {};
    scanPush(step, slice, z);
    if (minorLo > minorHi) return;
    scanHorizons(step, slice, z, lines.horizon);
    texelTangents(slice, lines, minorLo, minorHi, out);
    return;
  }
  updateHulls(slice, lines);
  if (minorLo > minorHi) return;  // the step only fills the hulls
  lineHorizons(slice, lines);
  texelTangents(slice, lines, minorLo, minorHi, out);
}

// Line samples: distance along u and height, linear across the line.
template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::lineSamples(int step, StepSlice& slice) const {
  const int major = slice.major, minorMax = minorMax_;
  slice.lineFirst = lines_;
  slice.lineLast = -1;
  for (int i = 0; i < lines_; ++i) {
    const double minor = (firstLine_ + i) + step * layout_.minorPerStep;
    if (minor < 0.0 || minor > minorMax) continue;
    slice.lineFirst = std::min(slice.lineFirst, i);
    slice.lineLast = i;
    slice.lineTD[i] = lineT(major, minor);
    slice.lineT[i] = static_cast<float>(slice.lineTD[i]);
  }
}

// The steepest slope from each line's new point (true height z[i]) to its
// points within the limit, the Earth's drop over the distance d taken
// off: (z' - z) / d - k d, as LineWalker's scan finds it from the dropped
// heights; the clamped edge's where within the limit too. The AVX2 scan
// does the same operations (a max as max_ps takes it).
template <bool kMajorIsColumn>
inline void BlockLineWalker<kMajorIsColumn>::scanHorizons(int step, const StepSlice& slice,
                                                          const float* z, float* horizon) const {
  const ScanRing& ring = *ring_;
  const float curvature = curvature_;
  std::fill(horizon, horizon + lines_, kNoHorizonTangent);
  for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
    float best = kNoHorizonTangent;
    for (int k = 1; k <= within_[i]; ++k) {
      const int slot = (step - k) & (kScanRing - 1);
      float slope;
      if (uniformSteps_) {
        slope = (ring.z[slot][i] - z[i]) * scanInverse_[k] - scanDrop_[k];
      } else {
        const float d = static_cast<float>(ring.t[slot][i] - slice.lineTD[i]);
        slope = (ring.z[slot][i] - z[i]) / d - curvature * d;
      }
      best = slope > best ? slope : best;
    }
    if (clampEdge_ && edgeWithin_[i]) {
      const float edge = clampedEdgeSlopeF(edgeZ_[i] - z[i], toEdge_[i], curvature);
      best = edge > best ? edge : best;
    }
    horizon[i] = best;
  }
}

// Hull update, line by line: pop what falls under the new point, and the
// point left behind it is the tangent point of its horizon.
template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::updateHulls(const StepSlice& slice, LineValues& lines) {
  const int majorLength = layout_.majorLength;
  const float curvature = curvature_, w = slice.w;
  for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
    lines.z[i] = (1.0f - w) * slice.heights[i + 1] + w * slice.heights[i + 2];
    lines.curvedZ[i] = lines.z[i] - curvature * slice.lineT[i] * slice.lineT[i];
  }
  for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
    HullPointF* hull = hulls_ + static_cast<size_t>(i) * hullStride(majorLength);
    const float t = slice.lineT[i], z = lines.curvedZ[i];
    if (size_[i] == 0) {
      edgeT_[i] = t;
      edgeZ_[i] = lines.z[i];
    }
    // Pops are rare beyond two per step: the first two are tested without
    // branches (which mispredict here), the loop takes the rest.
    const auto under = [&](int m) { return hullTopUnder(hull, m, t, z); };
    int n = size_[i];
    n -= (n >= 2 && under(n)) ? 1 : 0;
    n -= (n >= 2 && under(n)) ? 1 : 0;
    while (n >= 2 && under(n)) --n;
    // No point ahead: a stand-in that gives kNoHorizonTangent below.
    lines.riseToNear[i] = n >= 1 ? hull[n - 1].z - z : kNoHorizonTangent;
    lines.runToNear[i] = n >= 1 ? hull[n - 1].t - t : 1.0f;
    hull[n] = {t, z};
    size_[i] = n + 1;
  }
}

// The tangent of each walked line's horizon (kNoHorizonTangent off the grid).
template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::lineHorizons(const StepSlice& slice,
                                                   LineValues& lines) const {
  const float curvature = curvature_;
  for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
    const float slope = lines.riseToNear[i] / lines.runToNear[i];
    lines.horizon[i] =
        slope <= kNoHorizonTangent ? kNoHorizonTangent : slope + 2.0f * curvature * slice.lineT[i];
  }
  if (clampEdge_) {
    for (int i = slice.lineFirst; i <= slice.lineLast; ++i) {
      lines.horizon[i] = std::max(
          lines.horizon[i],
          clampedEdgeSlopeF(edgeZ_[i] - lines.z[i], edgeT_[i] - slice.lineT[i], curvature));
    }
  }
  for (int i = 0; i < slice.lineFirst; ++i) lines.horizon[i] = kNoHorizonTangent;
  for (int i = std::max(slice.lineLast + 1, 0); i < lines_; ++i) {
    lines.horizon[i] = kNoHorizonTangent;
  }
}

// The texels: blend their two lines, at least the leaving slope.
template <bool kMajorIsColumn>
void BlockLineWalker<kMajorIsColumn>::texelTangents(const StepSlice& slice, const LineValues& lines,
                                                    int minorLo, int minorHi, float* out) const {
  const float w = slice.w;
  const float* heights = slice.heights;
  const int texelFirst = minorLo - slice.base, texelLast = minorHi - slice.base;
  for (int i = texelFirst; i <= texelLast; ++i) {
    const float nearLine = lines.horizon[i], farLine = lines.horizon[i - 1];
    const float blended = nearLine + w * (farLine - nearLine);
    const float blend = (farLine <= kNoHorizonTangent || w == 0.0f) ? nearLine
                        : nearLine <= kNoHorizonTangent             ? farLine
                                                                    : blended;
    const float own = heights[i + 1];
    const float invCellMajor = kMajorIsColumn ? slice.invCellX[i + 1] : invCellY_;
    const float invCellMinor = kMajorIsColumn ? invCellY_ : slice.invCellX[i + 1];
    const float leaving =
        wMajorNeighbour_ * (slice.nextSlice[i + 1] - own) * invCellMajor +
        wMinorNeighbour_ * (heights[i + 1 + dMinorNeighbour_] - own) * invCellMinor;
    const int minorNeighbour = slice.base + i + dMinorNeighbour_;
    const bool offGrid = slice.offGridMajor || (wMinorNeighbour_ > 0.0f &&
                                                (minorNeighbour < 0 || minorNeighbour > minorMax_));
    out[i - texelFirst] = std::max(blend, offGrid ? kNoHorizonTangent : leaving);
    if (slice.east) texelSlopes(slice, i, i - texelFirst);
  }
}

// The slopes of the texel after walked line i, to east[j] and north[j], as
// BakeTerrain::slopeEastAt and slopeNorthAt compute them.
template <bool kMajorIsColumn>
inline void BlockLineWalker<kMajorIsColumn>::texelSlopes(const StepSlice& slice, int i,
                                                         int j) const {
  const float* heights = slice.heights;
  const int minor = slice.base + i;
  const float minorScale =
      BakeTerrain::differenceScale(std::max(minor - 1, 0), std::min(minor + 1, minorMax_));
  if constexpr (kMajorIsColumn) {  // major: column, minor: row
    slice.east[j] = (slice.majorHigh[i + 1] - slice.majorLow[i + 1]) *
                    (slice.majorScale * slice.invCellX[i + 1]);
    slice.north[j] = (heights[i] - heights[i + 2]) * (minorScale * invCellY_);
  } else {  // major: row, minor: column
    slice.east[j] = (heights[i + 2] - heights[i]) * (minorScale * slice.invCellX[i + 1]);
    slice.north[j] =
        (slice.majorLow[i + 1] - slice.majorHigh[i + 1]) * (slice.majorScale * invCellY_);
  }
}

template class BlockLineWalker<true>;
template class BlockLineWalker<false>;

}  // namespace aal::detail
