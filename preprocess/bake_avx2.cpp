// The bake's AVX2 kernels, for CPUs that have it (chosen at run time,
// detail::horizonAvx2): the block sweep's line walk 8 lines at a time
// (BlockLineWalker::stepAvx2) and the slice accumulator 8 texels at a time
// (addSlicesAvx2). Each gives the scalar path's results bit for bit: the
// same operations in the same order, and no fused multiply-adds. The
// functions target AVX2 without FMA, and so must any added here: where FMA
// is enabled GCC fuses the intrinsics' multiplies and adds too, which
// changed 0.23 % of a 1024² bake's texels (docs/baking.md, "Alternatives
// measured").
// The file is compiled for plain x86-64; only these functions are AVX2
// code, so nothing in it that the linker may share with other files is.
#include <algorithm>
#include <cstddef>
#include <iterator>

#include "aperture/preprocess/block_line_walker.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/sky_slice.h"
#include "aperture/preprocess/slice_accumulator.h"

#if AAL_HORIZON_AVX2
#include <immintrin.h>

namespace aal {

namespace {

// skySliceTerms for 8 texels, transposed (terms[c] holds term[c] of each
// lane), with the same operations in the same order: the same results bit
// for bit where the caller is compiled without FMA (GCC fuses intrinsics'
// multiplies and adds where it may).
__attribute__((target("avx2"))) inline void skySliceTermsAvx2(__m256 terms[4], __m256 tanTheta0,
                                                              float dPhi, float cosPhiDPhi,
                                                              float sinPhiDPhi) {
  const __m256 t = tanTheta0, one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f);
  const __m256 inv = _mm256_div_ps(one, _mm256_add_ps(one, _mm256_mul_ps(t, t)));
  const __m256 sinTheta = _mm256_mul_ps(t, _mm256_sqrt_ps(inv));
  // fastAtan(t): std::max(a, m) is a < m ? m : a, and max_ps(m, a) the same.
  const __m256 sign = _mm256_set1_ps(-0.0f);
  const __m256 a = _mm256_andnot_ps(sign, t);
  const __m256 inverted = _mm256_cmp_ps(a, one, _CMP_GT_OQ);
  const __m256 inverse = _mm256_div_ps(one, _mm256_max_ps(_mm256_set1_ps(1e-30f), a));
  const __m256 y = _mm256_blendv_ps(a, inverse, inverted);
  const __m256 y2 = _mm256_mul_ps(y, y);
  // atanUnit's polynomial, in its order.
  __m256 p = _mm256_set1_ps(static_cast<float>(kAtanUnitCoefficients[0]));
  for (size_t i = 1; i < std::size(kAtanUnitCoefficients); ++i) {
    p = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(kAtanUnitCoefficients[i])),
                      _mm256_mul_ps(y2, p));
  }
  const __m256 series = _mm256_mul_ps(y, p);
  const __m256 unsignedTheta = _mm256_blendv_ps(
      series, _mm256_sub_ps(_mm256_set1_ps(static_cast<float>(kSliceHalfPi)), series), inverted);
  const __m256 theta = _mm256_or_ps(unsignedTheta, _mm256_and_ps(sign, t));
  const __m256 ic = _mm256_sub_ps(_mm256_sub_ps(_mm256_set1_ps(static_cast<float>(kSliceQuarterPi)),
                                                _mm256_mul_ps(half, theta)),
                                  _mm256_mul_ps(_mm256_mul_ps(half, t), inv));
  terms[0] = _mm256_mul_ps(_mm256_set1_ps(cosPhiDPhi), ic);
  terms[1] = _mm256_mul_ps(_mm256_set1_ps(sinPhiDPhi), ic);
  terms[2] = _mm256_mul_ps(_mm256_set1_ps(dPhi), _mm256_mul_ps(half, inv));
  terms[3] = _mm256_mul_ps(_mm256_set1_ps(dPhi), _mm256_sub_ps(one, sinTheta));
}

// The terms of slice s at 8 texels (sliceTerms), transposed.
__attribute__((target("avx2"), always_inline)) inline void sliceTermsAvx2(__m256 terms[4],
                                                                          __m256 east, __m256 north,
                                                                          const float* tanHorizon,
                                                                          __m256i mask,
                                                                          const AzimuthSlice& s) {
  const __m256 tanPlane = _mm256_add_ps(_mm256_mul_ps(east, _mm256_set1_ps(s.cosPhi)),
                                        _mm256_mul_ps(north, _mm256_set1_ps(s.sinPhi)));
  // std::max(tanHorizon, tanPlane) in the same lane order.
  const __m256 t = _mm256_max_ps(tanPlane, _mm256_maskload_ps(tanHorizon, mask));
  skySliceTermsAvx2(terms, t, s.dPhi, s.cosPhiDPhi, s.sinPhiDPhi);
}

}  // namespace

namespace detail {

// SliceAccumulator::addBlock's sums 8 texels at a time, for CPUs with AVX2: the
// same operations in the same order as the vector loops of the scalar path, so
// the same sums bit for bit. Without FMA: fused multiply-adds (which GCC
// would form from these intrinsics) measured 1-3 % faster, within the
// noise on 2 threads, and would make a bake's result depend on the CPU.
__attribute__((target("avx2"))) void addSlicesAvx2(float* sums, const HorizonBlock& b,
                                                   const AzimuthSlice& s,
                                                   const AzimuthSlice* opposite) {
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (int j = 0; j < b.count; j += 8) {
    const int n = std::min(8, b.count - j);
    const __m256i mask = _mm256_cmpgt_epi32(_mm256_set1_epi32(n), iota);
    const size_t first = b.firstTexel + j * b.stride;
    const __m256 east = _mm256_maskload_ps(b.slopeEast + j, mask);
    const __m256 north = _mm256_maskload_ps(b.slopeNorth + j, mask);
    __m256 terms[4];
    sliceTermsAvx2(terms, east, north, b.tanHorizon + j, mask, s);
    if (opposite) {
      __m256 oppositeTerms[4];
      sliceTermsAvx2(oppositeTerms, east, north, b.tanOpposite + j, mask, *opposite);
      for (int c = 0; c < 4; ++c) terms[c] = _mm256_add_ps(terms[c], oppositeTerms[c]);
    }
    // Back to one vector of 4 sums per texel: quads k and k + 4 share a
    // register.
    const __m256 xy0 = _mm256_unpacklo_ps(terms[0], terms[1]);
    const __m256 xy1 = _mm256_unpackhi_ps(terms[0], terms[1]);
    const __m256 zw0 = _mm256_unpacklo_ps(terms[2], terms[3]);
    const __m256 zw1 = _mm256_unpackhi_ps(terms[2], terms[3]);
    const __m256 quads[4] = {_mm256_shuffle_ps(xy0, zw0, _MM_SHUFFLE(1, 0, 1, 0)),
                             _mm256_shuffle_ps(xy0, zw0, _MM_SHUFFLE(3, 2, 3, 2)),
                             _mm256_shuffle_ps(xy1, zw1, _MM_SHUFFLE(1, 0, 1, 0)),
                             _mm256_shuffle_ps(xy1, zw1, _MM_SHUFFLE(3, 2, 3, 2))};
    for (int k = 0; k < n; ++k) {
      float* sum = sums + 4 * (first + k * b.stride);
      const __m128 quad =
          k < 4 ? _mm256_castps256_ps128(quads[k & 3]) : _mm256_extractf128_ps(quads[k & 3], 1);
      _mm_storeu_ps(sum, _mm_add_ps(_mm_loadu_ps(sum), quad));
    }
  }
}

namespace {

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

// The top two points of 8 lines' hulls, a = hull[n - 1] and b =
// hull[n - 2], and the hulls' sizes n.
struct LaneHullTops {
  __m256 aT, aZ, bT, bZ;
  __m256i n;
};

// Pops from 8 lines' hulls (lanes `valid`, lane i's hull from points[first[i]])
// what falls under the lanes' new points (t, curvedZ): each round tests all
// lanes at once and gathers the next point down only for the lanes that
// popped, until no lane pops. A lane that pops in round k takes
// hull[n0 - 3 - k] for b, whatever the other lanes did: in round 0 the
// cached third point (thirdT, thirdZ), later a gather issued before the
// round's test, off the tests' dependency chain (clamped to the line's own
// points; what lanes that stopped read is not used).
__attribute__((target("avx2"), always_inline)) inline void popUnderAvx2(
    LaneHullTops& top, __m256 thirdT, __m256 thirdZ, __m256 t, __m256 curvedZ, __m256i valid,
    __m256i first, const long long* points) {
  const __m256i one = _mm256_set1_epi32(1);
  // A gather of 4 points (t, z pairs) per half: lanes 0, 1, 4, 5 and 2, 3,
  // 6, 7, so that one shuffle per coordinate puts the 8 back in order.
  const __m256i indexLow = _mm256_setr_epi32(0, 1, 4, 5, 0, 0, 0, 0);
  const __m256i indexHigh = _mm256_setr_epi32(2, 3, 6, 7, 0, 0, 0, 0);
  const __m256i maskLow = _mm256_setr_epi32(0, 0, 1, 1, 4, 4, 5, 5);
  const __m256i maskHigh = _mm256_setr_epi32(2, 2, 3, 3, 6, 6, 7, 7);
  __m256 aT = top.aT, aZ = top.aZ, bT = top.bT, bZ = top.bZ;
  __m256 nextT = thirdT, nextZ = thirdZ;
  __m256i n = top.n;
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
    const __m256 under =
        _mm256_cmp_ps(_mm256_mul_ps(_mm256_sub_ps(bZ, curvedZ), _mm256_sub_ps(aT, t)),
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
  top = {aT, aZ, bT, bZ, n};
}

// The lanes of walked lines `line` (8 indices) that are on the grid at a
// step: lineFirst .. lineLast.
__attribute__((target("avx2"), always_inline)) inline __m256i linesOnGridAvx2(__m256i line,
                                                                              int lineFirst,
                                                                              int lineLast) {
  return _mm256_and_si256(_mm256_cmpgt_epi32(line, _mm256_set1_epi32(lineFirst - 1)),
                          _mm256_cmpgt_epi32(_mm256_set1_epi32(lineLast + 1), line));
}

// The scan's slope to the k-th points back of 8 lines (their heights at
// z), as scanHorizons takes it with uniform steps.
__attribute__((target("avx2"), always_inline)) inline __m256 scannedSlopeAvx2(const float* z,
                                                                              __m256 zq,
                                                                              float inverse,
                                                                              float drop) {
  return _mm256_sub_ps(_mm256_mul_ps(_mm256_sub_ps(_mm256_load_ps(z), zq), _mm256_set1_ps(inverse)),
                       _mm256_set1_ps(drop));
}

// The same, kNoHorizonTangent in lanes with fewer than k points within the
// limit.
__attribute__((target("avx2"), always_inline)) inline __m256 scannedSlopeAvx2(
    const float* z, __m256 zq, float inverse, float drop, __m256i within, int k) {
  const __m256 active = _mm256_castsi256_ps(_mm256_cmpgt_epi32(within, _mm256_set1_epi32(k - 1)));
  return _mm256_blendv_ps(_mm256_set1_ps(kNoHorizonTangent), scannedSlopeAvx2(z, zq, inverse, drop),
                          active);
}

}  // namespace

// step() for CPUs with AVX2: the scalar walk's steps in vector code.
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) void BlockLineWalker<kMajorIsColumn>::stepAvx2(
    int step, int minorLo, int minorHi, float* out, float* east, float* north) {
  StepSlice slice;
  prefetchAhead(step);
  loadSlice<true>(step, east, north, slice);
  lineSamplesAvx2(step, slice);
  const bool texels = minorLo <= minorHi;
  alignas(32) float lineHorizon[kPaddedLines + 8];
  if (scan_) {
    alignas(32) float z[kPaddedLines] = {};
    scanPush(step, slice, z);
    if (texels) scanHorizonsAvx2(step, slice, z, lineHorizon);
  } else {
    updateHullsAvx2(slice, texels, lineHorizon);
  }
  if (texels) texelTangentsAvx2(slice, lineHorizon, minorLo, minorHi, out);
}

// The line samples' distances along u, 4 lines at a time in double
// precision: the same operations as the scalar loop.
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::lineSamplesAvx2(
    int step, StepSlice& slice) const {
  const int minorMax = minorMax_, major = slice.major;
  float* lineT = slice.lineT;
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
    _mm256_store_pd(slice.lineTD + i, t);
    _mm_storeu_ps(lineT + i, _mm256_cvtpd_ps(t));
  }
  validBits &= lines_ >= 64 ? ~0ull : (1ull << lines_) - 1;
  slice.lineFirst = lines_;
  slice.lineLast = -1;
  if (validBits) {
    slice.lineFirst = __builtin_ctzll(validBits);
    slice.lineLast = 63 - __builtin_clzll(validBits);
  }
}

// Pushes each walked line's new point onto its hull, 8 lines at a time,
// and with texels, writes the lines' horizon tangents to lineHorizon
// (kNoHorizonTangent off the grid).
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::updateHullsAvx2(
    const StepSlice& slice, bool texels, float* lineHorizon) {
  const int majorLength = layout_.majorLength, lines = lines_;
  alignas(32) float lineCurvedZ[kPaddedLines];
  const __m256 noHorizon = _mm256_set1_ps(kNoHorizonTangent);
  const __m256 w = _mm256_set1_ps(slice.w), w1 = _mm256_set1_ps(1.0f - slice.w);
  const __m256 curvature = _mm256_set1_ps(curvature_);
  const __m256 twoCurvature = _mm256_set1_ps(2.0f * curvature_);
  const long long* points = reinterpret_cast<const long long*>(hulls_);
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i one = _mm256_set1_epi32(1);
  for (int c = 0; c < lines; c += 8) {
    const __m256i line = _mm256_add_epi32(_mm256_set1_epi32(c), iota);
    const __m256i valid = linesOnGridAvx2(line, slice.lineFirst, slice.lineLast);
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

    LaneHullTops top{_mm256_load_ps(topT_ + c), _mm256_load_ps(topZ_ + c),
                     _mm256_load_ps(belowT_ + c), _mm256_load_ps(belowZ_ + c), n};
    popUnderAvx2(top, _mm256_load_ps(thirdT_ + c), _mm256_load_ps(thirdZ_ + c), t, curvedZ, valid,
                 _mm256_mullo_epi32(line, _mm256_set1_epi32(hullStride(majorLength))), points);
    const __m256 aT = top.aT, aZ = top.aZ, bT = top.bT, bZ = top.bZ;
    n = top.n;
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
    hulls_[static_cast<size_t>(i) * hullStride(majorLength) + size_[i] - 1] = {slice.lineT[i],
                                                                               lineCurvedZ[i]};
  }
}

// scanHorizons 8 lines at a time: each k-th point back of 8 lines is one
// row of the ring; lanes with fewer points within the limit are masked.
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::scanHorizonsAvx2(
    int step, const StepSlice& slice, const float* z, float* lineHorizon) const {
  const ScanRing& ring = *ring_;
  const __m256 noHorizon = _mm256_set1_ps(kNoHorizonTangent);
  const __m256 curvature = _mm256_set1_ps(curvature_);
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  for (int c = 0; c < lines_; c += 8) {
    const __m256i line = _mm256_add_epi32(_mm256_set1_epi32(c), iota);
    const __m256i valid = linesOnGridAvx2(line, slice.lineFirst, slice.lineLast);
    if (_mm256_testz_si256(valid, valid)) {
      _mm256_store_ps(lineHorizon + c, noHorizon);
      continue;
    }
    const __m256 zq = _mm256_load_ps(z + c);
    const __m256d tLow = _mm256_load_pd(slice.lineTD + c),
                  tHigh = _mm256_load_pd(slice.lineTD + c + 4);
    const __m256i within = _mm256_load_si256(reinterpret_cast<const __m256i*>(within_ + c));
    __m256 best = noHorizon;
    const int most = withinMax_[c / 8];
    if (uniformSteps_) {
      // Two running maxima, so that the loop is not one max's latency a
      // point (the maximum is the same whichever takes a point). Up to
      // the fewest points any line on the grid has within the limit no
      // lane is masked (lanes off the grid are dropped below).
      __m256 other = noHorizon;
      const int fewest = std::min(withinFewest_[c / 8], most);
      int k = 1;
      for (; k < fewest; k += 2) {
        best = _mm256_max_ps(scannedSlopeAvx2(ring.z[(step - k) & (kScanRing - 1)] + c, zq,
                                              scanInverse_[k], scanDrop_[k]),
                             best);
        other = _mm256_max_ps(scannedSlopeAvx2(ring.z[(step - k - 1) & (kScanRing - 1)] + c, zq,
                                               scanInverse_[k + 1], scanDrop_[k + 1]),
                              other);
      }
      for (; k < most; k += 2) {
        best = _mm256_max_ps(scannedSlopeAvx2(ring.z[(step - k) & (kScanRing - 1)] + c, zq,
                                              scanInverse_[k], scanDrop_[k], within, k),
                             best);
        other =
            _mm256_max_ps(scannedSlopeAvx2(ring.z[(step - k - 1) & (kScanRing - 1)] + c, zq,
                                           scanInverse_[k + 1], scanDrop_[k + 1], within, k + 1),
                          other);
      }
      if (k == most) {
        best = _mm256_max_ps(scannedSlopeAvx2(ring.z[(step - k) & (kScanRing - 1)] + c, zq,
                                              scanInverse_[k], scanDrop_[k], within, k),
                             best);
      }
      best = _mm256_max_ps(other, best);
    } else {
      for (int k = 1; k <= most; ++k) {
        const int slot = (step - k) & (kScanRing - 1);
        const __m256 d = _mm256_set_m128(
            _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_load_pd(ring.t[slot] + c + 4), tHigh)),
            _mm256_cvtpd_ps(_mm256_sub_pd(_mm256_load_pd(ring.t[slot] + c), tLow)));
        const __m256 slope =
            _mm256_sub_ps(_mm256_div_ps(_mm256_sub_ps(_mm256_load_ps(ring.z[slot] + c), zq), d),
                          _mm256_mul_ps(curvature, d));
        const __m256 active =
            _mm256_castsi256_ps(_mm256_cmpgt_epi32(within, _mm256_set1_epi32(k - 1)));
        best = _mm256_max_ps(_mm256_blendv_ps(noHorizon, slope, active), best);
      }
    }
    if (clampEdge_) {
      const __m256 edge = clampedEdgeSlopeAvx2(_mm256_sub_ps(_mm256_load_ps(edgeZ_ + c), zq),
                                               _mm256_load_ps(toEdge_ + c), curvature_);
      const __m256 edgeWithin =
          _mm256_castsi256_ps(_mm256_load_si256(reinterpret_cast<const __m256i*>(edgeWithin_ + c)));
      best = _mm256_max_ps(_mm256_blendv_ps(noHorizon, edge, edgeWithin), best);
    }
    _mm256_store_ps(lineHorizon + c, _mm256_blendv_ps(noHorizon, best, _mm256_castsi256_ps(valid)));
  }
}

// The texels: blend their two lines, at least the leaving slope, in lanes
// of 8 texels; the lines' tangents by lane shifts in registers (shifted
// loads of what was just stored would stall on store forwarding).
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::texelTangentsAvx2(
    const StepSlice& slice, const float* lineHorizon, int minorLo, int minorHi, float* out) const {
  const __m256 noHorizon = _mm256_set1_ps(kNoHorizonTangent);
  const __m256 w = _mm256_set1_ps(slice.w);
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  // Texel j lies between lines j + texelFirst - 1 and j + texelFirst.
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
    if (slice.east) texelSlopesAvx2(slice, i, j);
  }
}

// The slopes of the 8 texels after walked line i, to east[j ..] and
// north[j ..], in the scalar loop's operations: the minor difference's
// scale is 1/2 but at the grid's edges.
template <bool kMajorIsColumn>
__attribute__((target("avx2"))) inline void BlockLineWalker<kMajorIsColumn>::texelSlopesAvx2(
    const StepSlice& slice, int i, int j) const {
  const __m256i iota = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i one = _mm256_set1_epi32(1);
  const __m256 invCellX = _mm256_loadu_ps(slice.invCellX + i + 1);
  const __m256 invCellY = _mm256_set1_ps(invCellY_);
  const __m256i minor = _mm256_add_epi32(_mm256_set1_epi32(slice.base + i), iota);
  const __m256i span =
      _mm256_sub_epi32(_mm256_min_epi32(_mm256_add_epi32(minor, one), _mm256_set1_epi32(minorMax_)),
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

template void BlockLineWalker<true>::stepAvx2(int, int, int, float*, float*, float*);
template void BlockLineWalker<false>::stepAvx2(int, int, int, float*, float*, float*);

}  // namespace detail

}  // namespace aal

#endif  // AAL_HORIZON_AVX2
