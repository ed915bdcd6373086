// The bake's directional horizons (BakeOptions::horizons, terrain/io/horizon_map.h)
// against a brute-force ray march over the bilinear surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/synthetic.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

double bilinear(const Heightfield& f, double x, double y) {
  const int x0 = std::clamp(int(std::floor(x)), 0, f.width - 2);
  const int y0 = std::clamp(int(std::floor(y)), 0, f.height - 2);
  const double fx = x - x0, fy = y - y0;
  return (1 - fy) * ((1 - fx) * f.at(x0, y0) + fx * f.at(x0 + 1, y0)) +
         fy * ((1 - fx) * f.at(x0, y0 + 1) + fx * f.at(x0 + 1, y0 + 1));
}

// The highest elevation angle seen from texel (col, row) in azimuth phi
// (counter-clockwise from east; rows grow south), marching over the
// bilinear surface in steps of 1/16 of a cell to the DEM's edge (open sky
// beyond it); -inf when nothing lies ahead.
double marchedHorizon(const Heightfield& f, int col, int row, double phi) {
  const double dx = std::cos(phi), dy = -std::sin(phi);
  const double z0 = f.at(col, row);
  double best = -std::numeric_limits<double>::infinity();
  for (double t = 1.0 / 16;; t += 1.0 / 16) {
    const double x = col + t * dx, y = row + t * dy;
    if (x < -1e-9 || y < -1e-9 || x > f.width - 1 + 1e-9 || y > f.height - 1 + 1e-9) break;
    const double distance = t * f.cellSizeXM;
    best = std::max(best, std::atan((bilinear(f, x, y) - z0) / distance));
  }
  return best;
}

// The sweep's own horizon on a diagonal (dc, dr = +-1): the steepest slope
// to the texel centres along it, or the bilinear surface's slope leaving the
// texel (one-sided differences), whichever is higher.
double diagonalHorizon(const Heightfield& f, int col, int row, int dc, int dr) {
  const double z0 = f.at(col, row), cell = f.cellSizeXM;
  double best = -std::numeric_limits<double>::infinity();
  for (int n = 1;
       col + n * dc >= 0 && col + n * dc < f.width && row + n * dr >= 0 && row + n * dr < f.height;
       ++n) {
    best = std::max(best, (f.at(col + n * dc, row + n * dr) - z0) / (n * cell * std::sqrt(2.0)));
  }
  if (col + dc >= 0 && col + dc < f.width && row + dr >= 0 && row + dr < f.height) {
    best = std::max(
        best, ((f.at(col + dc, row) - z0) + (f.at(col, row + dr) - z0)) / (std::sqrt(2.0) * cell));
  }
  return std::atan(best);
}

// 48 x 40 fBm of 800 m relief on 30 m cells: most texels see a raised
// horizon in some direction.
Heightfield roughTerrain() {
  SyntheticTerrainOptions s;
  s.width = 48;
  s.height = 40;
  s.cellSizeM = 30;
  s.amplitudeM = 800;
  s.featureSizeTexels = 24;
  return makeSyntheticTerrain(s);
}

TEST(HorizonBake, StoredHorizonsFollowARayMarchInEveryDirection) {
  const Heightfield field = roughTerrain();
  BakeOptions o;
  o.azimuths = 64;
  o.horizons = true;
  const BakeResult bake = bakeApertures(field, o);
  const HorizonMap& map = bake.horizons;
  ASSERT_EQ(map.width, field.width);
  ASSERT_EQ(map.height, field.height);
  ASSERT_EQ(map.codes.size(), field.texelCount() * kHorizonDirections);

  double worstAxis = 0, worstDiagonal = 0, meanDiagonal = 0;
  int diagonals = 0, shadowing = 0;
  for (int k = 0; k < kHorizonDirections; ++k) {
    const double phi = k * 2 * kPi / kHorizonDirections;
    for (int row = 0; row < field.height; ++row) {
      for (int col = 0; col < field.width; ++col) {
        const double marched = marchedHorizon(field, col, row, phi);
        const uint8_t code = map.texel(col, row)[k];
        const double stored = decodeHorizon(code);
        // What the 8-bit code can hold of the march: its own rounding.
        const double held = decodeHorizon(encodeHorizon(float(marched)));
        const double step = decodeHorizon(uint8_t(std::min(255, code + 1))) -
                            decodeHorizon(uint8_t(std::max(0, code - 1)));
        const double error = std::abs(stored - held);
        if (marched > kHorizonMinRad) ++shadowing;
        if (k % 2 == 0) {
          // Along the axes the profile over the bilinear surface is linear
          // between texel centres, which the sweep's lines pass through: the
          // same horizon but for float rounding at a code's boundary.
          EXPECT_LE(error, step + 1e-6) << "direction " << k << " texel " << col << "," << row;
          worstAxis = std::max(worstAxis, error);
        } else {
          // On diagonals the bilinear surface bulges between texel centres
          // (a quadratic along the line), which the sweep's lines do not
          // see: its horizon is that of the centres (brute force), and where
          // the profile is concave the surface's slope leaving the texel,
          // which the march's first step (1/16 cell) only approaches.
          const int dc = k == 1 || k == 7 ? 1 : -1, dr = k == 1 || k == 3 ? -1 : 1;
          const double centres =
              decodeHorizon(encodeHorizon(float(diagonalHorizon(field, col, row, dc, dr))));
          EXPECT_LE(std::abs(stored - centres), step + 1e-6)
              << "direction " << k << " texel " << col << "," << row;
          worstDiagonal = std::max(worstDiagonal, error);
          meanDiagonal += error;
          ++diagonals;
        }
      }
    }
  }
  std::printf(
      "horizons vs ray march: %d of %zu horizons above the minimum; worst along axes "
      "%.4f rad, on diagonals %.4f rad (mean %.5f)\n",
      shadowing, map.codes.size(), worstAxis, worstDiagonal, meanDiagonal / diagonals);
  // Measured 0.0033 rad (0.19 degrees) on average, 0.08 at worst.
  EXPECT_LT(meanDiagonal / diagonals, 0.01);
  // The terrain is rough enough for the test to mean something.
  EXPECT_GT(shadowing, int(map.codes.size() / 4));
}

// 4-bit codes of sixteen directions: along the axes (where the sweep's
// lines pass through texel centres and its horizon is the march's) each
// stored code is the level nearest the marched horizon but at a level's
// boundary; in every direction the 8-bit bake's horizon re-coded is the
// same level, or (where the 8-bit rounding crossed a 4-bit boundary) the next.
TEST(HorizonBake, FourBitCodesHoldTheMarchedHorizonToTheNearestLevel) {
  const Heightfield field = roughTerrain();
  BakeOptions o;
  o.azimuths = 64;
  o.horizons = true;
  o.horizonDirections = 16;
  o.horizonBits = 4;
  const HorizonMap four = bakeApertures(field, o).horizons;
  ASSERT_EQ(four.bits, 4);
  ASSERT_EQ(four.codes.size(), field.texelCount() * 16);
  int checked = 0, raised = 0;
  for (int k = 0; k < 16; k += 4) {  // east, north, west, south
    const double phi = k * 2 * kPi / 16;
    for (int row = 0; row < field.height; ++row) {
      for (int col = 0; col < field.width; ++col) {
        const double marched = marchedHorizon(field, col, row, phi);
        const uint8_t code = four.texel(col, row)[k];
        ASSERT_LE(code, 15);
        const double stored = decodeHorizon(code, 4);
        if (marched > kHorizonMinRad) ++raised;
        // The nearest level, or its neighbour where the march lies within
        // float rounding of the midpoint between two levels.
        const double kept = std::min(marched, double(kHorizon4BitMaxRad));
        const double nearest = decodeHorizon(encodeHorizon(float(marched), 4), 4);
        if (std::abs(stored - nearest) > 1e-6) {
          const double mid = 0.5 * (stored + nearest);
          EXPECT_NEAR(kept, mid, 1e-5) << "direction " << k << " texel " << col << "," << row;
        }
        ++checked;
      }
    }
  }
  EXPECT_GT(raised, checked / 4) << "rough enough to mean something";
  o.horizonBits = 8;
  const HorizonMap eight = bakeApertures(field, o).horizons;
  size_t same = 0;
  for (size_t i = 0; i < eight.codes.size(); ++i) {
    const int recoded = encodeHorizon(decodeHorizon(eight.codes[i]), 4);
    ASSERT_LE(std::abs(int(four.codes[i]) - recoded), 1) << i;
    same += size_t(four.codes[i] == recoded);
  }
  EXPECT_GT(same, eight.codes.size() * 95 / 100);
  o.horizonBits = 6;
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
}

// Sixteen directions hold the eight's in their even slots: the same sweeps.
TEST(HorizonBake, SixteenDirectionsHoldTheEight) {
  SyntheticTerrainOptions s;
  s.width = 40;
  s.height = 33;
  s.amplitudeM = 800;
  s.featureSizeTexels = 16;
  const Heightfield field = makeSyntheticTerrain(s);
  BakeOptions o;
  o.azimuths = 32;
  o.horizons = true;
  const HorizonMap eight = bakeApertures(field, o).horizons;
  o.horizonDirections = 16;
  const HorizonMap sixteen = bakeApertures(field, o).horizons;
  ASSERT_EQ(sixteen.directions, 16);
  ASSERT_EQ(sixteen.codes.size(), 2 * eight.codes.size());
  int differentOdd = 0;
  for (int row = 0; row < field.height; ++row) {
    for (int col = 0; col < field.width; ++col) {
      for (int k = 0; k < 8; ++k) {
        ASSERT_EQ(sixteen.texel(col, row)[2 * k], eight.texel(col, row)[k]) << col << "," << row;
        // The odd directions are new: not simply the neighbours' mean.
        const int mean = (eight.texel(col, row)[k] + eight.texel(col, row)[(k + 1) % 8] + 1) / 2;
        if (std::abs(int(sixteen.texel(col, row)[2 * k + 1]) - mean) > 2) ++differentOdd;
      }
    }
  }
  EXPECT_GT(differentOdd, int(field.texelCount()));
  o.horizonDirections = 6;
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
}

TEST(HorizonBake, OptionsTheHorizonsCannotComeFromAreRefused) {
  SyntheticTerrainOptions s;
  s.width = s.height = 16;
  const Heightfield field = makeSyntheticTerrain(s);
  BakeOptions o;
  o.horizons = true;
  o.azimuths = 36;  // no azimuth at 45 degrees
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
  o.azimuths = 64;
  o.method = BakeMethod::Rays;
  EXPECT_THROW(bakeApertures(field, o), std::invalid_argument);
  // Without the option a bake has no horizons and is otherwise the same.
  o.method = BakeMethod::Sweep;
  const BakeResult with = bakeApertures(field, o);
  o.horizons = false;
  const BakeResult without = bakeApertures(field, o);
  EXPECT_TRUE(without.horizons.codes.empty());
  EXPECT_EQ(with.aperture.texels, without.aperture.texels);
}

}  // namespace
}  // namespace aal
