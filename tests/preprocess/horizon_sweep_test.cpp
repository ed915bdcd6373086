// The line sweep's horizons equal a brute-force maximum over the same lines.
#include "aperture/preprocess/horizon_sweep.h"

#include <gtest/gtest.h>

#include <limits>
#include <map>
#include <numbers>
#include <random>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/preprocess/bake_test_util.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

struct Case {
  double phi;
  HorizonSweepOptions options;
};

// Brute force along axis-aligned or diagonal lines, where the digital line
// through a texel is the exact grid line: the largest slope
// (z_q - z_p - k d^2) / d over the texels q ahead of p in direction u.
double bruteForceHorizon(const Heightfield& f, int col, int row, int dc, int dr, double cell,
                         const HorizonSweepOptions& o) {
  const double stepM = cell * std::sqrt(double(dc * dc + dr * dr));
  double best = -std::numeric_limits<double>::infinity();
  int n = 1;
  for (;
       col + n * dc >= 0 && col + n * dc < f.width && row + n * dr >= 0 && row + n * dr < f.height;
       ++n) {
    const double d = n * stepM;
    if (o.maxDistanceM > 0 && d > o.maxDistanceM) continue;
    const double rise = double(f.at(col + n * dc, row + n * dr)) - double(f.at(col, row));
    best = std::max(best, (rise - o.curvature * d * d) / d);
  }
  // The bilinear surface leaving p: one-sided differences into the cell ahead
  // (a neighbour is needed only along the axes the direction moves on).
  const bool haveX = dc == 0 || (col + dc >= 0 && col + dc < f.width);
  const bool haveY = dr == 0 || (row + dr >= 0 && row + dr < f.height);
  if (haveX && haveY) {
    const double norm = std::sqrt(double(dc * dc + dr * dr));
    const double z = f.at(col, row);
    double slope = 0;
    if (dc != 0) slope += std::abs(dc) / norm * (f.at(col + dc, row) - z) / cell;
    if (dr != 0) slope += std::abs(dr) / norm * (f.at(col, row + dr) - z) / cell;
    best = std::max(best, slope);
  }
  const int edgeN = n - 1;  // the last texel in the grid along u
  if (o.clampEdge) {
    const double toEdge = edgeN * stepM;
    if (o.maxDistanceM <= 0 || toEdge <= o.maxDistanceM) {
      const float edgeZ = f.at(col + edgeN * dc, row + edgeN * dr);
      best = std::max(best, detail::clampedEdgeSlope(double(edgeZ) - double(f.at(col, row)), toEdge,
                                                     o.curvature));
    }
  }
  return best;
}

// The sweep's horizon at every texel of `s`'s field, for each of the
// variants, along the 8 axis and diagonal directions, against the brute
// force.
void expectBruteForceHorizons(const SyntheticTerrainOptions& s,
                              const std::vector<HorizonSweepOptions>& variants) {
  const Heightfield field = makeSyntheticTerrain(s);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  // phi -> grid step (dc, dr): east, north-east, north, ... (rows grow south).
  const std::map<int, std::pair<int, int>> directions = {{0, {1, 0}},   {1, {1, -1}}, {2, {0, -1}},
                                                         {3, {-1, -1}}, {4, {-1, 0}}, {5, {-1, 1}},
                                                         {6, {0, 1}},   {7, {1, 1}}};
  for (const HorizonSweepOptions& o : variants) {
    for (const auto& [eighth, step] : directions) {
      std::vector<double> horizon(field.texelCount(), std::nan(""));
      sweepHorizons(terrain, eighth * kPi / 4, o,
                    [&](size_t i, double tanH) { horizon[i] = tanH; });
      for (int row = 0; row < field.height; ++row) {
        for (int col = 0; col < field.width; ++col) {
          const double expected =
              bruteForceHorizon(field, col, row, step.first, step.second, s.cellSizeM, o);
          const double got = horizon[field.index(col, row)];
          ASSERT_FALSE(std::isnan(got)) << "texel not visited";
          if (std::isinf(expected)) {
            ASSERT_TRUE(std::isinf(got) && got < 0) << col << "," << row;
          } else {
            ASSERT_NEAR(got, expected, 1e-9 + 1e-9 * std::abs(expected))
                << "phi=" << eighth << "/8 turn, texel " << col << "," << row
                << " clamp=" << o.clampEdge << " curvature=" << o.curvature
                << " maxDistance=" << o.maxDistanceM;
          }
        }
      }
    }
  }
}

constexpr double kCurve = (1 - 0.13) / (2 * 6371000.0);

TEST(HorizonSweep, EqualsBruteForceAlongAxisAndDiagonalLines) {
  SyntheticTerrainOptions s;
  s.width = 37;
  s.height = 37;
  s.cellSizeM = 500;
  s.amplitudeM = 2000;
  s.featureSizeTexels = 12;
  expectBruteForceHorizons(s, {{false, 0.0, 0.0},
                               {false, kCurve, 0.0},
                               {true, 0.0, 0.0},
                               {true, kCurve, 0.0},
                               {false, 0.0, 4100.0},
                               {true, kCurve, 6100.0}});
}

// Limits of more than 40 steps are not scanned point by point: each line
// keeps the upper hulls of its last two chunks (LineWalker::pushWithin).
// The same brute force, over limits that cut the lines into chunks of
// different lengths and phases.
TEST(HorizonSweep, LongLimitsEqualBruteForceAlongAxisAndDiagonalLines) {
  SyntheticTerrainOptions s;
  s.width = 131;
  s.height = 97;
  s.cellSizeM = 100;
  s.amplitudeM = 1500;
  s.featureSizeTexels = 8;
  const Heightfield field = makeSyntheticTerrain(s);
  ASSERT_GT(detail::stepsCovering(prepareBakeTerrain(field), 4700.0), 40);
  expectBruteForceHorizons(s, {{false, 0.0, 4700.0},
                               {true, kCurve, 6350.0},
                               {false, kCurve, 9100.0},
                               {true, 0.0, 20000.0}});
}

TEST(HorizonSweep, VisitsEveryTexelOnceForAnyAzimuth) {
  const Heightfield field = test::makeField(23, 31, 10.0, [](double, double) { return 0.0; });
  const BakeTerrain terrain = prepareBakeTerrain(field);
  for (int a = 0; a < 97; ++a) {
    std::vector<int> visits(field.texelCount(), 0);
    sweepHorizons(terrain, a * 2 * kPi / 97, {}, [&](size_t i, double) { ++visits[i]; });
    for (int v : visits) ASSERT_EQ(v, 1) << "azimuth " << a;
  }
}

TEST(HorizonSweep, ClampedEdgeOfFlatGroundIsTheHorizontal) {
  EXPECT_EQ(detail::clampedEdgeSlope(0.0, 0.0, 0.0), 0.0);
  EXPECT_EQ(detail::clampedEdgeSlope(-5.0, 100.0, 0.0), 0.0);
  EXPECT_TRUE(std::isinf(detail::clampedEdgeSlope(5.0, 100.0, 0.0)));
  // With curvature the far flat ground dips below the horizontal.
  const double k = 1.0 / (2 * 6371000.0);
  EXPECT_NEAR(detail::clampedEdgeSlope(-100.0, 10.0, k), -std::sqrt(2 * 100.0 / 6371000.0), 1e-12);
}

}  // namespace
}  // namespace aal
