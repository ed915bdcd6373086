// The horizons prefiltered as moments (terrain/light/horizon_moments.h)
// against the brute-force mean of the sun's visible fraction over the DEM
// texels of a footprint, on the rugged fBm of docs/comparison.md's horizon
// table, and against the mip heuristic they replace (the mean of the lower
// two of each 2 x 2).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/horizon_moments.h"
#include "aperture/terrain/light/lighting.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/synthetic.h"

namespace aal {
namespace {

constexpr float kDegree = std::numbers::pi_v<float> / 180.0f;

// One stored direction's horizons over the DEM (rad), row by row.
struct HorizonLayer {
  int width = 0, height = 0;
  std::vector<float> rad;
  float at(int x, int y) const { return rad[size_t(y) * size_t(width) + size_t(x)]; }
};

HorizonLayer decodedDirection(const HorizonMap& map, int direction) {
  HorizonLayer layer{map.width, map.height, {}};
  layer.rad.reserve(size_t(map.width) * size_t(map.height));
  for (int y = 0; y < map.height; ++y) {
    for (int x = 0; x < map.width; ++x) {
      layer.rad.push_back(decodeHorizon(map.texel(x, y)[direction], map.bits));
    }
  }
  return layer;
}

// The levels before: each texel the mean of the lower two of the 2 x 2 below.
float lowerTwoOf(float a, float b, float c, float d) {
  std::array<float, 4> v{a, b, c, d};
  std::sort(v.begin(), v.end());
  return (v[0] + v[1]) * 0.5f;
}

// Level `level`'s texel over the block of 2^level texels at (x0, y0): the
// heuristic's and the moments', reduced level by level as the device does.
struct BlockLevels {
  float lowerTwo = 0;
  HorizonMoments moments;
};
BlockLevels reduceBlock(const HorizonLayer& layer, int x0, int y0, int level) {
  const int n = 1 << level;
  std::vector<float> lower;
  std::vector<HorizonMoments> moments;
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      lower.push_back(layer.at(x0 + x, y0 + y));
      moments.push_back(horizonMomentsOf(layer.at(x0 + x, y0 + y)));
    }
  }
  for (int side = n; side > 1; side /= 2) {
    const int half = side / 2;
    std::vector<float> coarserLower;
    std::vector<HorizonMoments> coarserMoments;
    for (int y = 0; y < half; ++y) {
      for (int x = 0; x < half; ++x) {
        const size_t a = size_t(2 * y * side + 2 * x), b = a + 1, c = a + size_t(side), d = c + 1;
        coarserLower.push_back(lowerTwoOf(lower[a], lower[b], lower[c], lower[d]));
        coarserMoments.push_back(horizonMomentsMip(moments[a], moments[b], moments[c], moments[d]));
      }
    }
    lower = std::move(coarserLower);
    moments = std::move(coarserMoments);
  }
  return {lower.front(), moments.front()};
}

// RMS over the footprints of (estimate - brute force).
struct Errors {
  double lowerTwo = 0, meanOnly = 0, moments = 0;
  int footprints = 0;
};

// Footprints: the blocks of one mip level's texels (2^level DEM texels
// across); the sun at `elevation` between two stored directions with weights
// `weights` (as horizonPairWeights gives): the brute force interpolates each
// texel's horizon with them and averages horizonSunFraction over the block.
Errors footprintErrors(const HorizonLayer& first, const HorizonLayer& second, int level,
                       float elevation, std::array<float, 2> weights) {
  const int n = 1 << level;
  Errors e;
  for (int y0 = 0; y0 + n <= first.height; y0 += n) {
    for (int x0 = 0; x0 + n <= first.width; x0 += n) {
      double truth = 0;
      for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
          const float h =
              weights[0] * first.at(x0 + x, y0 + y) + weights[1] * second.at(x0 + x, y0 + y);
          truth += horizonSunFraction(elevation, h, kSunRadiusRad);
        }
      }
      truth /= double(n) * n;
      const BlockLevels a = reduceBlock(first, x0, y0, level);
      const BlockLevels b = reduceBlock(second, x0, y0, level);
      const HorizonSpread spread = horizonPairSpread(a.moments, b.moments, weights);
      const double lowerTwo = horizonSunFraction(
          elevation, weights[0] * a.lowerTwo + weights[1] * b.lowerTwo, kSunRadiusRad);
      const double meanOnly = horizonSunFraction(elevation, spread.mean, kSunRadiusRad);
      const double moments =
          horizonMomentSunFraction(elevation, spread.mean, spread.variance, kSunRadiusRad);
      e.lowerTwo += (lowerTwo - truth) * (lowerTwo - truth);
      e.meanOnly += (meanOnly - truth) * (meanOnly - truth);
      e.moments += (moments - truth) * (moments - truth);
      ++e.footprints;
    }
  }
  e.lowerTwo = std::sqrt(e.lowerTwo / e.footprints);
  e.meanOnly = std::sqrt(e.meanOnly / e.footprints);
  e.moments = std::sqrt(e.moments / e.footprints);
  return e;
}

// The sun's visible fraction over footprints of 2 to 32 texels across
// (levels 1 to 5) of the rugged fBm (aal-synth --size 256 --amplitude 2500
// --feature-size 64, 30 m cells; 16 directions of 8 bits), suns at 3, 5, 8
// and 12 degrees, on a stored direction and halfway between two: RMS error
// against the brute-force mean over the footprint's texels. Measured (RMS
// over the footprints, lower two / mean only / moments):
//   on a direction, level 1: 0.159-0.188 / 0.161-0.172 / 0.068-0.070
//                   level 3: 0.332-0.356 / 0.233-0.245 / 0.085-0.110
//                   level 5: 0.513-0.577 / 0.307-0.329 / 0.084-0.105
//   halfway,        level 1: 0.151-0.189 / 0.147-0.164 / 0.067
//                   level 5: 0.572-0.588 / 0.276-0.318 / 0.083-0.092
// The moments' error is 0.14-0.44 of the lower two's (0.28 on average), and falls with the
// footprint where the heuristic's grows. (Also measured, not kept: a
// Gaussian of the moments convolved with the disk, within +-10 % of these;
// Chebyshev's one-sided bound, 2.3-3.5x these; the halfway variance from
// the weighted second moments, whose spread between the two directions
// doubled the error at level 1: docs/rendering.md, "Prefiltering the
// horizons: moments".)
TEST(HorizonMoments, ExpectedSunFractionIsFarCloserThanTheLowerTwo) {
  SyntheticTerrainOptions terrain;
  terrain.width = terrain.height = 256;
  terrain.amplitudeM = 2500;
  terrain.featureSizeTexels = 64;
  BakeOptions bake;
  bake.horizons = true;
  bake.horizonDirections = 16;
  const HorizonMap map = bakeApertures(makeSyntheticTerrain(terrain), bake).horizons;
  // Directions 11 and 12 of 16: compass 292.5 and 270 degrees, suns in the
  // west over a rugged terrain.
  const HorizonLayer first = decodedDirection(map, 11), second = decodedDirection(map, 12);
  double worstRatio = 0, sumRatio = 0;
  int cases = 0;
  for (const std::array<float, 2> weights : {std::array{1.0f, 0.0f}, std::array{0.5f, 0.5f}}) {
    for (const float degrees : {3.0f, 5.0f, 8.0f, 12.0f}) {
      for (int level = 1; level <= 5; ++level) {
        const Errors e = footprintErrors(first, second, level, degrees * kDegree, weights);
        std::printf(
            "weights %.1f/%.1f, sun %4.1f deg, level %d (%5d footprints): RMS error lower two "
            "%.4f, mean only %.4f, moments %.4f\n",
            weights[0], weights[1], degrees, level, e.footprints, e.lowerTwo, e.meanOnly,
            e.moments);
        EXPECT_LT(e.moments, 0.5 * e.lowerTwo) << degrees << " deg, level " << level;
        EXPECT_LT(e.moments, 0.5 * e.meanOnly) << degrees << " deg, level " << level;
        EXPECT_LT(e.moments, 0.12) << degrees << " deg, level " << level;
        worstRatio = std::max(worstRatio, e.moments / e.lowerTwo);
        sumRatio += e.moments / e.lowerTwo;
        ++cases;
      }
    }
  }
  std::printf("moments / lower two: mean %.2f, worst %.2f\n", sumRatio / cases, worstRatio);
  EXPECT_LT(sumRatio / cases, 0.35);
}

// One texel (no spread) reads as the straight horizon; a negative variance
// (half-float rounding) as none; a spread widens the penumbra symmetrically.
TEST(HorizonMoments, NoSpreadIsTheTexelsOwnHorizon) {
  const float e = 5.0f * kDegree, r = kSunRadiusRad;
  for (const float h : {e - 2 * r, e - 0.5f * r, e, e + 0.3f * r, e + 2 * r}) {
    EXPECT_FLOAT_EQ(horizonMomentSunFraction(e, h, 0.0f, r), horizonSunFraction(e, h, r));
    EXPECT_FLOAT_EQ(horizonMomentSunFraction(e, h, -1e-6f, r), horizonSunFraction(e, h, r));
  }
  const HorizonSpread one =
      horizonPairSpread(horizonMomentsOf(0.1f), horizonMomentsOf(0.3f), {0.25f, 0.75f});
  EXPECT_FLOAT_EQ(one.mean, 0.25f);
  EXPECT_NEAR(one.variance, 0.0f, 1e-8f);  // each direction's own spread: none
  // Half of a footprint 4 sun radii below the sun, half 4 above: about half lit.
  const HorizonMoments split =
      horizonMomentsMip(horizonMomentsOf(e - 4 * r), horizonMomentsOf(e + 4 * r),
                        horizonMomentsOf(e - 4 * r), horizonMomentsOf(e + 4 * r));
  const HorizonSpread s = horizonPairSpread(split, split, {1.0f, 0.0f});
  EXPECT_NEAR(s.variance, 16 * r * r, 1e-9f);
  EXPECT_NEAR(horizonMomentSunFraction(e, s.mean, s.variance, r), 0.5f, 1e-4f);
  EXPECT_GT(horizonMomentSunFraction(e, e + 2 * r, s.variance, r), 0.0f);
  EXPECT_LT(horizonMomentSunFraction(e, e - 2 * r, s.variance, r), 1.0f);
}

}  // namespace
}  // namespace aal
