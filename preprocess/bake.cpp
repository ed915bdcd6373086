#include "bake.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "bake_terrain.h"
#include "far_horizon.h"
#include "horizon_blocks.h"
#include "horizon_sweep.h"
#include "huge_pages.h"
#include "ray_bake.h"
#include "sky_slice.h"

namespace aal {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void checkOptions(const Heightfield& field, const BakeOptions& o) {
  // The whole field, or a band of its rows (Heightfield::firstRow).
  const bool rows = field.width > 0 && field.z.size() % static_cast<size_t>(field.width) == 0 &&
                    field.firstRow >= 0 && field.residentRows() >= 1 &&
                    field.firstRow + field.residentRows() <= field.height;
  if (field.width < 1 || field.height < 1 || !rows) {
    throw std::invalid_argument("bake: empty or inconsistent heightfield");
  }
  if (o.azimuths < 4 || o.azimuths > 4096) {
    throw std::invalid_argument("azimuths must be in [4, 4096]");
  }
  if (o.rays < 16 || o.rays > 1 << 20) throw std::invalid_argument("rays must be in [16, 2^20]");
  if (!(o.maxDistanceM >= 0.0) || !std::isfinite(o.maxDistanceM)) {
    throw std::invalid_argument("max distance must be >= 0");
  }
  if (!(o.refraction >= 0.0 && o.refraction < 1.0)) {
    throw std::invalid_argument("refraction coefficient must be in [0, 1)");
  }
  if (o.horizons && !validHorizonDirections(o.horizonDirections)) {
    throw std::invalid_argument("horizon directions must be 4, 8, 12 or 16");
  }
  if (o.horizons && !validHorizonBits(o.horizonBits)) {
    throw std::invalid_argument("horizon codes must have 8 or 4 bits");
  }
  if (o.horizons && (o.method != BakeMethod::Sweep || o.azimuths % o.horizonDirections != 0)) {
    throw std::invalid_argument("directional horizons need the sweep with a multiple of " +
                                std::to_string(o.horizonDirections) + " azimuths");
  }
}

void checkCancel(const BakeOptions& o) {
  if (o.cancel && o.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
}

// One azimuth's constants, in the single precision the slices are summed
// in (sky_slice.h).
struct Slice {
  double phi;
  float cosPhi, sinPhi, dPhi, cosPhiDPhi, sinPhiDPhi;
  int horizonSlot = -1;  // direction of the horizon map this azimuth fills, or -1
};

#if AAL_HORIZON_AVX2
// The terms of slice s at 8 texels (sliceTerms), transposed.
__attribute__((target("avx2"), always_inline)) inline void sliceTermsAvx2(__m256 terms[4],
                                                                          __m256 east, __m256 north,
                                                                          const float* tanHorizon,
                                                                          __m256i mask,
                                                                          const Slice& s) {
  const __m256 tanPlane = _mm256_add_ps(_mm256_mul_ps(east, _mm256_set1_ps(s.cosPhi)),
                                        _mm256_mul_ps(north, _mm256_set1_ps(s.sinPhi)));
  // std::max(tanHorizon, tanPlane) in the same lane order.
  const __m256 t = _mm256_max_ps(tanPlane, _mm256_maskload_ps(tanHorizon, mask));
  skySliceTermsAvx2(terms, t, s.dPhi, s.cosPhiDPhi, s.sinPhiDPhi);
}

// addSlices' sums 8 texels at a time, for CPUs with AVX2: the same
// operations in the same order as the vector loops of the scalar path, so
// the same sums bit for bit. Without FMA: fused multiply-adds (which GCC
// would form from these intrinsics) measured 1-3 % faster, within the
// noise on 2 threads, and would make a bake's result depend on the CPU.
__attribute__((target("avx2"))) void addSlicesAvx2(float* sums, const HorizonBlock& b,
                                                   const Slice& s, const Slice* opposite) {
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
#endif

// Sums the sky slices of every azimuth into `sums`, and the SVF terms; with
// `horizonCodes`, stores the horizons of the azimuths k * 2 pi /
// o.horizonDirections there (that many codes per texel).
void sweepAllAzimuths(const BakeTerrain& terrain, const BakeOptions& o, float* sums,
                      std::vector<float>& svf, uint8_t* horizonCodes) {
  HorizonSweepOptions sweep;
  sweep.clampEdge = o.clampEdge;
  sweep.curvature = o.curvature ? (1.0 - o.refraction) / (2.0 * kEarthRadiusM) : 0.0;
  sweep.maxDistanceM = o.maxDistanceM;
  if (o.farField && o.maxDistanceM <= 0.0) sweep.windowReachM = o.farField->options.nearReachM;
  const double dPhi = kTwoPi / o.azimuths;
  const bool wantSvf = !svf.empty();

  const auto sliceOf = [&](int a) {
    const double phi = a * dPhi, cosPhi = std::cos(phi), sinPhi = std::sin(phi);
    const bool stored = a * o.horizonDirections % o.azimuths == 0;
    return Slice{phi,
                 static_cast<float>(cosPhi),
                 static_cast<float>(sinPhi),
                 static_cast<float>(dPhi),
                 static_cast<float>(cosPhi * dPhi),
                 static_cast<float>(sinPhi * dPhi),
                 stored ? a * o.horizonDirections / o.azimuths : -1};
  };
  // The horizon elevations of slice s at a block's texels, encoded.
  const auto storeHorizons = [&](const HorizonBlock& b, const float* tanHorizon, const Slice& s) {
    for (int j = 0; j < b.count; ++j) {
      horizonCodes[(b.firstTexel + j * b.stride) * size_t(o.horizonDirections) +
                   size_t(s.horizonSlot)] = encodeHorizon(std::atan(tanHorizon[j]), o.horizonBits);
    }
  };
  constexpr int kLines = HorizonBlock::kLines;
  const bool avx2 = detail::horizonAvx2();
  const auto addSvf = [&](const HorizonBlock& b, const float* tanHorizon) {
    for (int j = 0; j < b.count; ++j) {
      const float t = tanHorizon[j];
      if (t > 0.0f) svf[b.firstTexel + j * b.stride] += t / std::sqrt(1.0f + t * t);
    }
  };
  // The terms of slice s at a block's texels, from their horizon tangents.
  // Directions below the tangent plane are outside the hemisphere.
  const auto sliceTerms = [&](const HorizonBlock& b, const float* tanHorizon, const Slice& s,
                              float(*terms)[4]) {
    for (int j = 0; j < b.count; ++j) {
      const float tanPlane = b.slopeEast[j] * s.cosPhi + b.slopeNorth[j] * s.sinPhi;
      skySliceTerms(terms[j], std::max(tanHorizon[j], tanPlane), s.dPhi, s.cosPhiDPhi,
                    s.sinPhiDPhi);
    }
    if (wantSvf) addSvf(b, tanHorizon);
  };
  // Adds slice s (and, from b.tanOpposite, the opposite slice) to a block of
  // texels in loops that compile to vector code, reading and writing each
  // texel's sums once.
  const auto addSlices = [&](const HorizonBlock& b, const Slice& s, const Slice* opposite) {
    // Here as well as between azimuths: one azimuth of a 32768^2 DEM takes
    // a minute. TBB carries the exception out of the sweep's parallel_for.
    checkCancel(o);
    if (horizonCodes) {
      if (s.horizonSlot >= 0) storeHorizons(b, b.tanHorizon, s);
      if (opposite && opposite->horizonSlot >= 0) storeHorizons(b, b.tanOpposite, *opposite);
    }
    // The texels a few steps on: their sums are a column apart or in
    // another row, where the hardware prefetcher does not look. Along a row,
    // one prefetch per cache line (4 texels' sums) and the last texel: 3 %
    // faster at 1024² than one per texel.
    if (b.stride == 1 && b.aheadCount > 0) {
      const size_t first = b.aheadFirstTexel, last = first + b.aheadCount - 1;
      for (size_t texel = first; texel < last; texel += 4) __builtin_prefetch(sums + 4 * texel, 1);
      __builtin_prefetch(sums + 4 * last, 1);
    } else {
      for (int j = 0; j < b.aheadCount; ++j) {
        __builtin_prefetch(sums + 4 * (b.aheadFirstTexel + j * b.stride), 1);
      }
    }
#if AAL_HORIZON_AVX2
    // Not for the distance-limited sweep's blocks of one: 20 % slower there.
    if (avx2 && b.count > 1) {
      addSlicesAvx2(sums, b, s, opposite);
      if (wantSvf) {
        addSvf(b, b.tanHorizon);
        if (opposite) addSvf(b, b.tanOpposite);
      }
      return;
    }
#endif
    float terms[kLines][4];
    sliceTerms(b, b.tanHorizon, s, terms);
    if (opposite) {
      float oppositeTerms[kLines][4];
      sliceTerms(b, b.tanOpposite, *opposite, oppositeTerms);
      for (int j = 0; j < b.count; ++j) {
        for (int c = 0; c < 4; ++c) terms[j][c] += oppositeTerms[j][c];
      }
    }
    for (int j = 0; j < b.count; ++j) {
      float* sum = sums + 4 * (b.firstTexel + j * b.stride);
      for (int c = 0; c < 4; ++c) sum[c] += terms[j][c];
    }
  };
  // The texel-by-texel sweeps hand over one texel: a block of one.
  const auto addTexelSlice = [&](size_t texel, double tanHorizon, const Slice& s) {
    const float tanH = std::max(static_cast<float>(tanHorizon), kNoHorizonTangent);
    const float east = terrain.slopeEast(texel), north = terrain.slopeNorth(texel);
    HorizonBlock b{texel, 1, 1, &tanH};
    b.slopeEast = &east;
    b.slopeNorth = &north;
    addSlices(b, s, nullptr);
  };
  const auto sweepOne = [&](const Slice& s) {
    if (sweep.windowReachM > 0.0) {
      // Near horizons from the window's lines, far ones from the pyramid.
      const FarHorizons far(*o.farField, terrain, s.phi, sweep.curvature, sweep.clampEdge);
      const TexelWindow& w = terrain.window;
      if (!sweep.clampEdge) {
        sweepWindowHorizonBlocks(terrain, s.phi, sweep, [&](const HorizonBlock& b) {
          alignas(32) float merged[HorizonBlock::kPaddedTexels];
          for (int j = 0; j < b.count; ++j) {
            const size_t texel = b.firstTexel + j * b.stride;
            const int col = w.col + static_cast<int>(texel % w.width);
            const int row = w.row + static_cast<int>(texel / w.width);
            const double tangent =
                far.mergedTangent(col, row, terrain.field->at(col, row), b.tanHorizon[j]);
            merged[j] = static_cast<float>(std::max(tangent, double(kNoHorizonTangent)));
          }
          HorizonBlock block = b;
          block.tanHorizon = merged;
          addSlices(block, s, nullptr);
        });
        return;
      }
      // Clamped edges: the general sweep knows where a line's walk began.
      sweepHorizons(terrain, s.phi, sweep, [&](size_t texel, double tanHorizon) {
        const int col = w.col + static_cast<int>(texel % w.width);
        const int row = w.row + static_cast<int>(texel / w.width);
        addTexelSlice(
            texel, std::max(tanHorizon, far.tangentAt(col, row, terrain.field->at(col, row))), s);
      });
    } else if (sweep.maxDistanceM > 0.0) {
      sweepHorizons(terrain, s.phi, sweep,
                    [&](size_t texel, double tanHorizon) { addTexelSlice(texel, tanHorizon, s); });
    } else {
      sweepHorizonBlocks(terrain, s.phi, sweep,
                         [&](const HorizonBlock& b) { addSlices(b, s, nullptr); });
    }
  };

  // Without a distance limit azimuths a and a + n/2 are swept together
  // (sweepOpposedHorizonBlocks): one pass over the sums for both.
  const bool opposed =
      sweep.maxDistanceM <= 0.0 && sweep.windowReachM <= 0.0 && o.azimuths % 2 == 0;
  const int passes = opposed ? o.azimuths / 2 : o.azimuths;
  for (int pass = 0; pass < passes; ++pass) {
    checkCancel(o);
    const Slice s = sliceOf(pass);
    if (!opposed) {
      sweepOne(s);
    } else {
      const Slice opposite = sliceOf(pass + passes);
      if (!sweepOpposedHorizonBlocks(terrain, s.phi, opposite.phi, sweep,
                                     [&](const HorizonBlock& b) { addSlices(b, s, &opposite); })) {
        sweepOne(s);
        sweepOne(opposite);
      }
    }
    if (o.progress) o.progress(static_cast<double>(pass + 1) / passes);
  }
  if (wantSvf) {
    tbb::parallel_for(size_t(0), svf.size(),
                      [&](size_t i) { svf[i] = 1.0f - svf[i] / o.azimuths; });
  }
}

// Turns the sums into unit bent normals and arc lengths, in place.
void finishApertures(const BakeTerrain& terrain, std::vector<float>& texels) {
  tbb::parallel_for(size_t(0), texels.size() / 4, [&](size_t i) {
    float* s = &texels[4 * i];
    double bx = s[0], by = s[1], bz = s[2];
    const double length = std::sqrt(bx * bx + by * by + bz * bz);
    if (length > 0.0) {
      bx /= length;
      by /= length;
      bz /= length;
    } else {  // nothing visible: fall back to the surface normal
      const double sx = terrain.slopeEast(i), sy = terrain.slopeNorth(i);
      const double n = std::sqrt(1.0 + sx * sx + sy * sy);
      bx = -sx / n;
      by = -sy / n;
      bz = 1.0 / n;
    }
    const double visible = std::clamp(s[3] / kTwoPi, 0.0, 1.0);
    s[0] = static_cast<float>(bx);
    s[1] = static_cast<float>(by);
    s[2] = static_cast<float>(bz);
    s[3] = static_cast<float>(std::acos(1.0 - visible));  // arc length of the cap
  });
}

// Bakes the texels of the terrain's window; info.sourceChecksum is left to
// the caller.
BakeResult bakeWindow(const Heightfield& field, const BakeTerrain& terrain, const BakeOptions& o) {
  // The running sums live in the output's own storage: 16 bytes per texel.
  BakeResult result;
  ApertureMap& map = result.aperture;
  map.width = terrain.window.width;
  map.height = terrain.window.height;
  assignOnHugePages(map.texels, map.texelCount() * 4, 0.0f);
  if (o.skyViewFactor) result.skyViewFactor.assign(map.texelCount(), 0.0f);
  if (o.horizons) {
    result.horizons.width = map.width;
    result.horizons.height = map.height;
    result.horizons.directions = o.horizonDirections;
    result.horizons.bits = o.horizonBits;
    result.horizons.codes.assign(map.texelCount() * size_t(o.horizonDirections), 0);
  }

  if (o.method == BakeMethod::Sweep) {
    sweepAllAzimuths(terrain, o, map.texels.data(), result.skyViewFactor,
                     o.horizons ? result.horizons.codes.data() : nullptr);
  } else {
    bakeRays(terrain, o, map.texels.data(), result.skyViewFactor);
  }
  finishApertures(terrain, map.texels);
  map.info = bakeInfo(field, o);
  return result;
}

}  // namespace

ApertureMapInfo bakeInfo(const Heightfield& field, const BakeOptions& o) {
  ApertureMapInfo info;
  info.azimuths = o.method == BakeMethod::Sweep ? o.azimuths : 0;
  info.method = o.method == BakeMethod::Sweep ? "sweep" : "rays";
  if (o.farField && o.maxDistanceM <= 0.0) info.method = farFieldMethod(o.farField->options);
  info.cellSizeX = field.cellSizeXM;
  info.cellSizeY = field.cellSizeYM;
  info.zScale = field.zScale;
  info.sourceWidth = field.width;
  info.sourceHeight = field.height;
  info.edge = o.clampEdge ? "clamp" : "open";
  info.curvature = o.curvature;
  info.refraction = o.curvature ? o.refraction : 0.0;
  info.maxDistanceM = o.maxDistanceM;
  return info;
}

BakeResult bakeApertures(const Heightfield& field, const BakeOptions& o) {
  checkOptions(field, o);
  if (field.z.size() != field.texelCount()) {
    throw std::invalid_argument("bake: a band of rows bakes only as windows");
  }
  // The DEM's checksum is one serial pass over its bytes (5 ms at 1024^2,
  // 2 % of the bake): a task beside the sweeps rather than a wait after them.
  std::string checksum;
  tbb::task_group beside;
  beside.run([&] { checksum = heightfieldChecksum(field); });
  BakeResult result;
  try {
    result = bakeWindow(field, prepareBakeTerrain(field), o);
  } catch (...) {
    beside.wait();
    throw;
  }
  beside.wait();
  result.aperture.info.sourceChecksum = checksum;
  return result;
}

BakeResult bakeApertureWindow(const Heightfield& field, const TexelWindow& window,
                              const BakeOptions& o) {
  checkOptions(field, o);
  if (!window.covers(field) &&
      (o.method != BakeMethod::Sweep || !(o.maxDistanceM > 0.0 || o.farField))) {
    throw std::invalid_argument("a bake window needs the sweep with a max distance or a far field");
  }
  return bakeWindow(field, prepareBakeTerrain(field, window), o);
}

}  // namespace aal
