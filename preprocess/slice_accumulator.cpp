#include "aperture/preprocess/slice_accumulator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <utility>

#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/openness.h"
#include "aperture/preprocess/sky_illumination.h"
#include "aperture/preprocess/sky_slice.h"

namespace aal {

namespace {

// The tangent of the texel's tangent plane (its slope) in slice s's azimuth.
inline float tanPlaneOf(const HorizonBlock& b, int j, const AzimuthSlice& s) {
  return b.slopeEast[j] * s.cosPhi + b.slopeNorth[j] * s.sinPhi;
}

}  // namespace

SliceAccumulator::SliceAccumulator(const BakeTerrain& terrain, const BakeOptions& o, float* sums,
                                   GisSums& gis, uint8_t* horizonCodes)
    : terrain_(terrain),
      o_(o),
      sums_(sums),
      gis_(gis),
      horizonCodes_(horizonCodes),
      avx2_(detail::horizonAvx2()) {}

void SliceAccumulator::addBlock(const HorizonBlock& b, const AzimuthSlice& s,
                                const AzimuthSlice* opposite) const {
  addSlices(b, s, opposite);
}

void SliceAccumulator::addRun(const HorizonRun& run, const AzimuthSlice& s) const {
  static_assert(HorizonRun::kMaxCount <= HorizonBlock::kLines);
  // A block: the run's tangents in single precision, and its slopes, in
  // whole vectors of 8 for addSlicesAvx2. (One texel at a time took 3 times
  // as long as the sums of a block.)
  alignas(32) float tanH[HorizonBlock::kPaddedTexels] = {};
  alignas(32) float east[HorizonBlock::kPaddedTexels] = {};
  alignas(32) float north[HorizonBlock::kPaddedTexels] = {};
  for (int j = 0; j < run.count; ++j) {
    tanH[j] = std::max(static_cast<float>(run.tanHorizon[j]), kNoHorizonTangent);
  }
  // The slopes only where a term takes the tangent plane (the sky-view
  // factor and openness do not): a tenth of a 1024² --svf bake within 10 km.
  if (sums_ != nullptr || !gis_.visible.empty() || !gis_.skyIllumination.empty()) {
    for (int j = 0; j < run.count; ++j) {
      const int minor = run.minorFirst + j;
      const int col = run.majorIsColumn ? run.major : minor;
      const int row = run.majorIsColumn ? minor : run.major;
      east[j] = terrain_.slopeEastAt(col, row);
      north[j] = terrain_.slopeNorthAt(col, row);
    }
  }
  const int first = run.minorFirst;
  HorizonBlock b{run.majorIsColumn ? terrain_.windowIndex(run.major, first)
                                   : terrain_.windowIndex(first, run.major),
                 run.majorIsColumn ? terrain_.pitch : 1, run.count, tanH};
  b.slopeEast = east;
  b.slopeNorth = north;
  addSlices(b, s, nullptr);
}

inline void SliceAccumulator::addSlices(const HorizonBlock& b, const AzimuthSlice& s,
                                        const AzimuthSlice* opposite) const {
  // Here as well as between azimuths: one azimuth of a 32768^2 DEM takes
  // a minute. TBB carries the exception out of the sweep's parallel_for.
  if (o_.cancel && o_.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
  if (horizonCodes_) {
    if (s.horizonSlot >= 0) storeHorizons(b, b.tanHorizon, s);
    if (opposite && opposite->horizonSlot >= 0) storeHorizons(b, b.tanOpposite, *opposite);
  }
  prefetchAhead(b);
  addGisTerms(b, s, opposite);
  if (sums_ == nullptr) return;  // no aperture map
#if AAL_HORIZON_AVX2
  // Not for blocks of one: 20 % slower there.
  if (avx2_ && b.count > 1) {
    detail::addSlicesAvx2(sums_, b, s, opposite);
    return;
  }
#endif
  // Loops that compile to vector code.
  float terms[HorizonBlock::kLines][4];
  sliceTerms(b, b.tanHorizon, s, terms);
  if (opposite) {
    float oppositeTerms[HorizonBlock::kLines][4];
    sliceTerms(b, b.tanOpposite, *opposite, oppositeTerms);
    for (int j = 0; j < b.count; ++j) {
      for (int c = 0; c < 4; ++c) terms[j][c] += oppositeTerms[j][c];
    }
  }
  for (int j = 0; j < b.count; ++j) {
    float* sum = sums_ + 4 * (b.firstTexel + j * b.stride);
    for (int c = 0; c < 4; ++c) sum[c] += terms[j][c];
  }
}

// The texels a few steps on: their sums are a column apart or in another
// row, where the hardware prefetcher does not look. Along a row, one
// prefetch per cache line (4 texels' sums) and the last texel: 3 % faster
// at 1024² than one per texel.
inline void SliceAccumulator::prefetchAhead(const HorizonBlock& b) const {
  if (b.aheadCount <= 0) return;
  if (b.stride == 1) {
    if (sums_ == nullptr) return;
    const size_t first = b.aheadFirstTexel, last = first + b.aheadCount - 1;
    for (size_t texel = first; texel < last; texel += 4) __builtin_prefetch(sums_ + 4 * texel, 1);
    __builtin_prefetch(sums_ + 4 * last, 1);
    return;
  }
  if (sums_ != nullptr) {
    for (int j = 0; j < b.aheadCount; ++j) {
      __builtin_prefetch(sums_ + 4 * (b.aheadFirstTexel + j * b.stride), 1);
    }
  }
  // The GIS rasters' sums likewise (one cache line per texel here).
  for (const std::vector<float>* g : std::as_const(gis_).all()) {
    if (g->empty()) continue;
    for (int j = 0; j < b.aheadCount; ++j) {
      __builtin_prefetch(g->data() + b.aheadFirstTexel + j * b.stride, 1);
    }
  }
}

// The horizon elevations of slice s at a block's texels, encoded.
inline void SliceAccumulator::storeHorizons(const HorizonBlock& b, const float* tanHorizon,
                                            const AzimuthSlice& s) const {
  for (int j = 0; j < b.count; ++j) {
    horizonCodes_[(b.firstTexel + j * b.stride) * size_t(o_.horizonDirections) +
                  size_t(s.horizonSlot)] = encodeHorizon(std::atan(tanHorizon[j]), o_.horizonBits);
  }
}

inline void SliceAccumulator::addGisTerms(const HorizonBlock& b, const AzimuthSlice& s,
                                          const AzimuthSlice* opposite) const {
  if (!gis_.svf.empty()) {
    addSkyViewFactor(b, b.tanHorizon, gis_.svf, 1.0f);
    if (opposite) addSkyViewFactor(b, b.tanOpposite, gis_.svf, 1.0f);
  }
  if (!gis_.openness.empty()) {
    addOpenness(b, b.tanHorizon);
    if (opposite) addOpenness(b, b.tanOpposite);
  }
  if (!gis_.anisotropicSvf.empty()) {
    addSkyViewFactor(b, b.tanHorizon, gis_.anisotropicSvf, s.anisotropicWeight);
    if (opposite) {
      addSkyViewFactor(b, b.tanOpposite, gis_.anisotropicSvf, opposite->anisotropicWeight);
    }
  }
  if (!gis_.skyIllumination.empty()) {
    addSkyIllumination(b, b.tanHorizon, s);
    if (opposite) addSkyIllumination(b, b.tanOpposite, *opposite);
  }
  if (!gis_.visible.empty()) addVisibleSky(b, b.tanHorizon, b.tanOpposite, s, opposite);
}

// The visible solid angle of slice s and the opposite one: the aperture
// sums' fourth term (sliceTerms) by the same operations in the same order,
// so that a bake without the map sums the same bits.
inline void SliceAccumulator::addVisibleSky(const HorizonBlock& b, const float* tanHorizon,
                                            const float* tanOpposite, const AzimuthSlice& s,
                                            const AzimuthSlice* opposite) const {
  float terms[HorizonBlock::kLines];
  for (int j = 0; j < b.count; ++j) {
    const float tanPlane = tanPlaneOf(b, j, s);
    terms[j] = visibleSliceTerm(std::max(tanHorizon[j], tanPlane), s.dPhi);
  }
  if (opposite) {
    for (int j = 0; j < b.count; ++j) {
      terms[j] +=
          visibleSliceTerm(std::max(tanOpposite[j], tanPlaneOf(b, j, *opposite)), opposite->dPhi);
    }
  }
  float* sum = gis_.visible.data() + b.firstTexel;
  for (int j = 0; j < b.count; ++j) sum[j * b.stride] += terms[j];
}

// Signed: openness counts terrain below the horizontal too.
inline void SliceAccumulator::addOpenness(const HorizonBlock& b, const float* tanHorizon) const {
  for (int j = 0; j < b.count; ++j) {
    addHorizonAngle(gis_.openness[b.firstTexel + j * b.stride], tanHorizon[j]);
  }
}

// The sine of the horizon's elevation above the horizontal, times weight.
// The terms first, without a branch (a horizon below the horizontal adds
// 0), so that they compile to vector code; then added at the texels'
// stride. (With the prefetch in prefetchAhead and the sums' padded pitch,
// sumsPitch: a 2048² --svf bake 10 % faster, docs/performance.md.)
inline void SliceAccumulator::addSkyViewFactor(const HorizonBlock& b, const float* tanHorizon,
                                               std::vector<float>& sums, float weight) const {
  float terms[HorizonBlock::kLines];
  for (int j = 0; j < b.count; ++j) {
    const float t = tanHorizon[j];
    terms[j] = weight * std::max(t, 0.0f) / std::sqrt(1.0f + t * t);
  }
  float* sum = sums.data() + b.firstTexel;
  for (int j = 0; j < b.count; ++j) sum[j * b.stride] += terms[j];
}

// The sky above the horizontal, the horizon and the tangent plane.
inline void SliceAccumulator::addSkyIllumination(const HorizonBlock& b, const float* tanHorizon,
                                                 const AzimuthSlice& s) const {
  for (int j = 0; j < b.count; ++j) {
    const float tanPlane = tanPlaneOf(b, j, s);
    const float t0 = std::max({0.0f, tanHorizon[j], tanPlane});
    gis_.skyIllumination[b.firstTexel + j * b.stride] +=
        skyIlluminationSlice(t0, tanPlane, o_.skyModel);
  }
}

// The terms of slice s at a block's texels, from their horizon tangents.
// Directions below the tangent plane are outside the hemisphere.
inline void SliceAccumulator::sliceTerms(const HorizonBlock& b, const float* tanHorizon,
                                         const AzimuthSlice& s, float (*terms)[4]) const {
  for (int j = 0; j < b.count; ++j) {
    const float tanPlane = tanPlaneOf(b, j, s);
    skySliceTerms(terms[j], std::max(tanHorizon[j], tanPlane), s.dPhi, s.cosPhiDPhi, s.sinPhiDPhi);
  }
}

}  // namespace aal
