// A bake's running sums of sky slices (docs/design.md §3 step 2): the
// visitor of the horizon sweeps (horizon_blocks.h, horizon_sweep.h), which
// adds each slice's closed-form terms (sky_slice.h) to the 4 floats of every
// texel it is given, and the sky-view factor's terms, the horizon angles of
// positive openness (openness.h) and the directional horizons where wanted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/horizon_blocks.h"

namespace aal {

struct HorizonRun;  // horizon_sweep.h

// One azimuth's constants, in the single precision the slices are summed
// in (sky_slice.h).
struct AzimuthSlice {
  double phi;
  float cosPhi, sinPhi, dPhi, cosPhiDPhi, sinPhiDPhi;
  int horizonSlot = -1;         // direction of the horizon map this azimuth fills, or -1
  float anisotropicWeight = 1;  // of the anisotropic sky-view factor (sky_illumination.h)
};

// The per-texel sums of the GIS outputs, each empty unless wanted: the
// sky-view factor's, the horizon angles of positive openness, the
// anisotropic sky-view factor's weighted terms, the sky illumination's, and
// the visible solid angle's where no aperture map is summed (with one, it
// is the map's fourth sum).
struct GisSums {
  std::vector<float> svf, openness, anisotropicSvf, skyIllumination, visible;

  // Every one of them, wanted or not (empty).
  std::array<std::vector<float>*, 5> all() {
    return {&svf, &openness, &anisotropicSvf, &skyIllumination, &visible};
  }
  std::array<const std::vector<float>*, 5> all() const {
    return {&svf, &openness, &anisotropicSvf, &skyIllumination, &visible};
  }
};

class SliceAccumulator {
 public:
  // sums: 4 floats per texel of terrain.window (bent vector, solid angle),
  // or null when no aperture map is baked (BakeOptions::apertureMap); gis: the GIS outputs' sums,
  // one float per texel where wanted; horizonCodes: null, or o.horizonDirections codes per texel.
  SliceAccumulator(const BakeTerrain& terrain, const BakeOptions& o, float* sums, GisSums& gis,
                   uint8_t* horizonCodes);

  // Adds slice s (and, from b.tanOpposite, the opposite slice) to a block
  // of texels, reading and writing each texel's sums once. Throws
  // BakeCancelled when o.cancel is set. Safe to call concurrently for
  // blocks of different texels.
  void addBlock(const HorizonBlock& b, const AzimuthSlice& s, const AzimuthSlice* opposite) const;
  // The same for a run of texels of the distance-limited sweep
  // (sweepHorizonRuns), with their slopes found from the heights.
  void addRun(const HorizonRun& run, const AzimuthSlice& s) const;

 private:
  // The body of addBlock and addRun, inlined into both.
  [[gnu::always_inline]] inline void addSlices(const HorizonBlock& b, const AzimuthSlice& s,
                                               const AzimuthSlice* opposite) const;
  [[gnu::always_inline]] inline void prefetchAhead(const HorizonBlock& b) const;
  [[gnu::always_inline]] inline void storeHorizons(const HorizonBlock& b, const float* tanHorizon,
                                                   const AzimuthSlice& s) const;
  // The GIS outputs' terms of both slices.
  [[gnu::always_inline]] inline void addGisTerms(const HorizonBlock& b, const AzimuthSlice& s,
                                                 const AzimuthSlice* opposite) const;
  [[gnu::always_inline]] inline void addSkyViewFactor(const HorizonBlock& b,
                                                      const float* tanHorizon,
                                                      std::vector<float>& sums, float weight) const;
  [[gnu::always_inline]] inline void addSkyIllumination(const HorizonBlock& b,
                                                        const float* tanHorizon,
                                                        const AzimuthSlice& s) const;
  [[gnu::always_inline]] inline void addOpenness(const HorizonBlock& b,
                                                 const float* tanHorizon) const;
  [[gnu::always_inline]] inline void addVisibleSky(const HorizonBlock& b, const float* tanHorizon,
                                                   const float* tanOpposite, const AzimuthSlice& s,
                                                   const AzimuthSlice* opposite) const;
  [[gnu::always_inline]] inline void sliceTerms(const HorizonBlock& b, const float* tanHorizon,
                                                const AzimuthSlice& s, float (*terms)[4]) const;

  const BakeTerrain& terrain_;
  const BakeOptions& o_;
  float* const sums_;
  GisSums& gis_;
  uint8_t* const horizonCodes_;
  const bool avx2_;
};

namespace detail {
#if AAL_HORIZON_AVX2
// SliceAccumulator::addBlock's sums 8 texels at a time, for CPUs with AVX2
// (bake_avx2.cpp).
__attribute__((target("avx2"))) void addSlicesAvx2(float* sums, const HorizonBlock& b,
                                                   const AzimuthSlice& s,
                                                   const AzimuthSlice* opposite);
#endif
}  // namespace detail

}  // namespace aal
