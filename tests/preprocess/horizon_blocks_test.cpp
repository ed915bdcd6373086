// The vectorised block sweep gives the reference sweep's horizons (to single
// precision), for every texel once, whatever the azimuth, edge mode,
// curvature and per-row cell size.
#include "aperture/preprocess/horizon_blocks.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/block_line_walker.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/terrain/synthetic.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

Heightfield roughTerrain(int width, int height, bool geographic) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 90;
  s.amplitudeM = 900;
  s.featureSizeTexels = 9;
  Heightfield field = makeSyntheticTerrain(s);
  if (geographic) {
    // Cells narrow towards the pole as on a latitude/longitude grid.
    field.rowCellSizeXM.resize(field.height);
    for (int row = 0; row < field.height; ++row) {
      field.rowCellSizeXM[row] = 90.0 * std::cos((50.0 + 0.2 * (field.height - row)) * kPi / 180);
    }
  }
  return field;
}

// Largest |a - b| relative to max(1, |b|) over the texels, with both "no
// horizon" markers taken as equal; fails on a texel visited other than once.
void expectSameHorizons(const BakeTerrain& terrain, double phi, const HorizonSweepOptions& o,
                        double tolerance = 2e-4) {
  const size_t texels = terrain.heights.dem->texelCount();
  std::vector<double> reference(texels, std::nan(""));
  sweepHorizons(terrain, phi, o, [&](size_t i, double tanH) { reference[i] = tanH; });
  std::vector<float> blocks(texels, std::nanf(""));
  std::vector<int> visits(texels, 0);
  sweepHorizonBlocks(terrain, phi, o, [&](const HorizonBlock& b) {
    for (int j = 0; j < b.count; ++j) {
      const size_t i = b.firstTexel + j * b.stride;
      blocks[i] = b.tanHorizon[j];
      ++visits[i];
    }
  });
  double worst = 0;
  for (size_t i = 0; i < texels; ++i) {
    ASSERT_EQ(visits[i], 1) << "texel " << i << " phi " << phi;
    const bool noneRef = std::isinf(reference[i]);
    const bool noneBlock = blocks[i] <= kNoHorizonTangent;
    ASSERT_EQ(noneRef, noneBlock) << "texel " << i << " phi " << phi << ": " << reference[i]
                                  << " vs " << blocks[i];
    if (!noneRef) {
      worst = std::max(worst,
                       std::abs(blocks[i] - reference[i]) / std::max(1.0, std::abs(reference[i])));
    }
  }
  EXPECT_LT(worst, tolerance) << "phi " << phi << " clamp " << o.clampEdge << " curvature "
                              << o.curvature << " limit " << o.maxDistanceM;
}

// The opposed sweep hands over both azimuths' tangents of every texel once;
// each must match its own reference sweep. Returns whether it paired.
bool expectSameOpposedHorizons(const BakeTerrain& terrain, double phi, double phiOpposite,
                               const HorizonSweepOptions& o, double tolerance = 2e-4) {
  const size_t texels = terrain.heights.dem->texelCount();
  std::vector<double> reference(texels), referenceOpposite(texels);
  sweepHorizons(terrain, phi, o, [&](size_t i, double tanH) { reference[i] = tanH; });
  sweepHorizons(terrain, phiOpposite, o,
                [&](size_t i, double tanH) { referenceOpposite[i] = tanH; });
  std::vector<float> blocks(texels), blocksOpposite(texels);
  std::vector<int> visits(texels, 0);
  const bool paired =
      sweepOpposedHorizonBlocks(terrain, phi, phiOpposite, o, [&](const HorizonBlock& b) {
        EXPECT_NE(b.tanOpposite, nullptr);
        for (int j = 0; j < b.count; ++j) {
          const size_t i = b.firstTexel + j * b.stride;
          blocks[i] = b.tanHorizon[j];
          blocksOpposite[i] = b.tanOpposite[j];
          ++visits[i];
        }
      });
  double worst = 0;
  for (size_t i = 0; i < texels; ++i) {
    if (!paired) {
      EXPECT_EQ(visits[i], 0) << "texel " << i << " phi " << phi;
      continue;
    }
    EXPECT_EQ(visits[i], 1) << "texel " << i << " phi " << phi;
    for (auto [ref, block] :
         {std::pair{reference[i], blocks[i]}, std::pair{referenceOpposite[i], blocksOpposite[i]}}) {
      EXPECT_EQ(std::isinf(ref), block <= kNoHorizonTangent)
          << "texel " << i << " phi " << phi << ": " << ref << " vs " << block;
      if (!std::isinf(ref)) {
        worst = std::max(worst, std::abs(block - ref) / std::max(1.0, std::abs(ref)));
      }
    }
  }
  EXPECT_LT(worst, tolerance) << "phi " << phi << " clamp " << o.clampEdge << " curvature "
                              << o.curvature << " limit " << o.maxDistanceM;
  return paired;
}

TEST(HorizonBlocks, MatchTheReferenceSweepForEveryAzimuth) {
  const Heightfield field = roughTerrain(45, 38, false);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  for (int a = 0; a < 48; ++a) expectSameHorizons(terrain, a * 2 * kPi / 48, {});
}

TEST(HorizonBlocks, MatchTheReferenceSweepWithClampedEdgesAndCurvature) {
  const Heightfield field = roughTerrain(33, 51, false);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  const double kCurve = (1 - 0.13) / (2 * 6371000.0);
  for (const HorizonSweepOptions& o :
       {HorizonSweepOptions{true, 0.0, 0.0}, HorizonSweepOptions{false, kCurve, 0.0},
        HorizonSweepOptions{true, kCurve, 0.0}}) {
    for (int a = 0; a < 24; ++a) expectSameHorizons(terrain, (a + 0.37) * 2 * kPi / 24, o);
  }
}

TEST(HorizonBlocks, MatchTheReferenceSweepOnAGeographicGrid) {
  const Heightfield field = roughTerrain(40, 40, true);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  for (int a = 0; a < 32; ++a) expectSameHorizons(terrain, a * 2 * kPi / 32 + 0.01, {});
}

TEST(HorizonBlocks, CoverNarrowAndTinyGrids) {
  for (auto [w, h] :
       {std::pair{1, 1}, std::pair{1, 7}, std::pair{9, 1}, std::pair{2, 3}, std::pair{17, 2}}) {
    const Heightfield field = roughTerrain(w, h, false);
    const BakeTerrain terrain = prepareBakeTerrain(field);
    for (int a = 0; a < 16; ++a) expectSameHorizons(terrain, a * 2 * kPi / 16 + 0.2, {});
  }
}

TEST(HorizonBlocks, OpposedSweepMatchesTheReferenceSweepsOfBothAzimuths) {
  const double kCurve = (1 - 0.13) / (2 * 6371000.0);
  for (auto [w, h, geographic] : {std::tuple{45, 38, false}, std::tuple{40, 40, true},
                                  std::tuple{1, 7, false}, std::tuple{17, 2, false}}) {
    const Heightfield field = roughTerrain(w, h, geographic);
    const BakeTerrain terrain = prepareBakeTerrain(field);
    int paired = 0;
    constexpr int kAzimuths = 48;
    const double dPhi = 2 * kPi / kAzimuths;
    for (int a = 0; a < kAzimuths / 2; ++a) {
      paired += expectSameOpposedHorizons(terrain, a * dPhi, (a + kAzimuths / 2) * dPhi, {});
    }
    // Only the diagonals may fail to pair (their major axes can differ).
    EXPECT_GE(paired, kAzimuths / 2 - 2) << w << "x" << h;
    for (const HorizonSweepOptions& o :
         {HorizonSweepOptions{true, 0.0, 0.0}, HorizonSweepOptions{true, kCurve, 0.0}}) {
      for (int a = 0; a < 12; ++a) {
        const double phi = (a + 0.37) * 2 * kPi / 24;
        EXPECT_TRUE(expectSameOpposedHorizons(terrain, phi, phi + kPi, o)) << phi;
      }
    }
  }
}

// Distance limits of up to kBlockScanSteps steps are scanned by the block
// walk (scansWithinLimit): each texel's tangent is the reference sweep's
// to single precision, for limits of one to 334 steps of 90 m cells and
// one to 193 of 48-58 m (the reference scans up to 40 steps in double
// precision and takes the longer ones from its chunks' hulls), with
// clamped edges and curvature, on a geographic grid (the scan's distances
// from the points' positions; elsewhere from a table per step), along
// lines longer than the scan's ring of steps and on a grid one row tall
// (row lines of one step: no table), for both sweeps. The
// tolerance is tighter than the hull walk's, so a wrong Earth drop (k d:
// 7e-5 at 1 km) would show.
TEST(HorizonBlocks, LimitsAreScannedAsTheReferenceSweepFindsThem) {
  const double kCurve = (1 - 0.13) / (2 * 6371000.0);
  constexpr double kTolerance = 1e-5;
  for (auto [w, h, geographic] :
       {std::tuple{45, 38, false}, std::tuple{40, 40, true}, std::tuple{1, 7, false},
        std::tuple{9, 1, false}, std::tuple{600, 6, false}}) {
    const Heightfield field = roughTerrain(w, h, geographic);
    const BakeTerrain terrain = prepareBakeTerrain(field);
    for (double limit : {90.0, 200.0, 450.0, 1000.0, 1500.0, 4000.0, 9000.0, 30000.0}) {
      for (bool clamp : {false, true}) {
        for (double curvature : {0.0, kCurve}) {
          const HorizonSweepOptions o{clamp, curvature, limit};
          if (!detail::scansWithinLimit(terrain, o)) {  // a geographic grid's cut-over
            EXPECT_TRUE(geographic && limit > 9000) << w << "x" << h << " limit " << limit;
            continue;
          }
          for (int a = 0; a < 16; ++a) {
            const double phi = (a + (clamp ? 0.37 : 0.0)) * 2 * kPi / 16;
            expectSameHorizons(terrain, phi, o, kTolerance);
            expectSameOpposedHorizons(terrain, phi, phi + kPi, o, kTolerance);
          }
        }
      }
    }
  }
}

// Longer limits are the general sweep's (LineWalker's chunks): the block
// sweeps refuse them rather than scan them slowly.
TEST(HorizonBlocks, RefuseLimitsTooLongToScan) {
  const Heightfield field = roughTerrain(45, 38, false);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  const HorizonSweepOptions o{false, 0.0, 50000.0};
  ASSERT_FALSE(detail::scansWithinLimit(terrain, o));
  const auto none = [](const HorizonBlock&) {};
  EXPECT_THROW(sweepHorizonBlocks(terrain, 0.3, o, none), std::invalid_argument);
  EXPECT_THROW(sweepOpposedHorizonBlocks(terrain, 0.3, 0.3 + kPi, o, none), std::invalid_argument);
}

// Runs the sweeps and bakes of its scope on the scalar path or, where the CPU
// has AVX2, the AVX2 path; AVX2 is allowed again after.
class Avx2Allowed {
 public:
  explicit Avx2Allowed(bool allowed) { setHorizonAvx2Allowed(allowed); }
  ~Avx2Allowed() { setHorizonAvx2Allowed(true); }
  Avx2Allowed(const Avx2Allowed&) = delete;
  Avx2Allowed& operator=(const Avx2Allowed&) = delete;
};

bool cpuHasAvx2() {
  const Avx2Allowed allowed(true);
  return detail::horizonAvx2();
}

// Every texel's tangent from sweepHorizonBlocks, then both tangents from
// sweepOpposedHorizonBlocks (NaN where not visited, and a last float that
// says whether the opposed sweep paired).
std::vector<float> blockTangents(const BakeTerrain& terrain, double phi,
                                 const HorizonSweepOptions& o) {
  const size_t texels = terrain.heights.dem->texelCount();
  std::vector<float> out(3 * texels + 1, std::nanf(""));
  sweepHorizonBlocks(terrain, phi, o, [&](const HorizonBlock& b) {
    for (int j = 0; j < b.count; ++j) out[b.firstTexel + j * b.stride] = b.tanHorizon[j];
  });
  const bool paired =
      sweepOpposedHorizonBlocks(terrain, phi, phi + kPi, o, [&](const HorizonBlock& b) {
        for (int j = 0; j < b.count; ++j) {
          const size_t i = b.firstTexel + j * b.stride;
          out[texels + 2 * i] = b.tanHorizon[j];
          out[texels + 2 * i + 1] = b.tanOpposite[j];
        }
      });
  out.back() = paired ? 1.0f : 0.0f;
  return out;
}

// The AVX2 walk (8 lines at a time, gathers, masked edge lanes) gives the
// scalar walk's tangents bit for bit: along rows and columns, at the
// diagonals and between, with clamped edges, curvature and short distance
// limits (the scan), on grids of one
// and of several groups of lines, and where cells narrow row by row.
TEST(HorizonBlocks, Avx2AndScalarWalksGiveTheSameTangents) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  const double kCurve = (1 - 0.13) / (2 * 6371000.0);
  const std::vector<double> azimuths = {0.0, kPi / 2, kPi,  3 * kPi / 2, kPi / 4, 3 * kPi / 4,
                                        0.3, 1.9,     2.61, 4.4,         5.95};
  for (auto [w, h, geographic] :
       {std::tuple{45, 38, false}, std::tuple{100, 70, false}, std::tuple{40, 40, true},
        std::tuple{67, 81, true}, std::tuple{1, 7, false}, std::tuple{17, 2, false}}) {
    const Heightfield field = roughTerrain(w, h, geographic);
    const BakeTerrain terrain = prepareBakeTerrain(field);
    for (const HorizonSweepOptions& o :
         {HorizonSweepOptions{false, 0.0, 0.0}, HorizonSweepOptions{true, 0.0, 0.0},
          HorizonSweepOptions{false, kCurve, 0.0}, HorizonSweepOptions{true, kCurve, 0.0},
          HorizonSweepOptions{false, 0.0, 450.0}, HorizonSweepOptions{true, kCurve, 1000.0}}) {
      for (double phi : azimuths) {
        std::vector<float> scalar, avx2;
        {
          const Avx2Allowed allowed(false);
          scalar = blockTangents(terrain, phi, o);
        }
        {
          const Avx2Allowed allowed(true);
          avx2 = blockTangents(terrain, phi, o);
        }
        ASSERT_EQ(scalar.size(), avx2.size());
        EXPECT_EQ(std::memcmp(scalar.data(), avx2.data(), scalar.size() * sizeof(float)), 0)
            << w << "x" << h << " phi " << phi << " clamp " << o.clampEdge << " curvature "
            << o.curvature;
      }
    }
  }
}

// The slopes every block carries (computed in the walk from the heights it
// loads) are the terrain's, bit for bit, on both paths, for sweeps along
// each axis both ways, diagonals, one-texel-wide grids and narrowing cells.
TEST(HorizonBlocks, EveryBlockCarriesItsTexelsSlopes) {
  const std::vector<double> azimuths = {0.0,         kPi / 2, kPi, 3 * kPi / 2, kPi / 4,
                                        3 * kPi / 4, 0.3,     1.9, 2.61,        4.4};
  for (auto [w, h, geographic] :
       {std::tuple{45, 38, false}, std::tuple{100, 70, false}, std::tuple{67, 81, true},
        std::tuple{1, 1, false}, std::tuple{1, 7, false}, std::tuple{17, 2, false}}) {
    const Heightfield field = roughTerrain(w, h, geographic);
    const BakeTerrain terrain = prepareBakeTerrain(field);
    for (const bool avx2 : {false, true}) {
      const Avx2Allowed allowed(avx2);
      for (double phi : azimuths) {
        std::atomic<size_t> checked = 0, wrong = 0;  // blocks come from several threads
        const auto check = [&](const HorizonBlock& b) {
          ASSERT_NE(b.slopeEast, nullptr);
          ASSERT_NE(b.slopeNorth, nullptr);
          for (int j = 0; j < b.count; ++j) {
            const size_t i = b.firstTexel + j * b.stride;
            const int col = static_cast<int>(i % w), row = static_cast<int>(i / w);
            const float east = terrain.slopeEastAt(col, row);
            const float north = terrain.slopeNorthAt(col, row);
            wrong += std::memcmp(&b.slopeEast[j], &east, sizeof(float)) != 0 ||
                     std::memcmp(&b.slopeNorth[j], &north, sizeof(float)) != 0;
            ++checked;
          }
        };
        sweepHorizonBlocks(terrain, phi, {}, check);
        if (!sweepOpposedHorizonBlocks(terrain, phi, phi + kPi, {}, check)) {
          checked += field.texelCount();  // the diagonal did not pair: nothing to check
        }
        EXPECT_EQ(checked.load(), 2 * field.texelCount()) << w << "x" << h << " phi " << phi;
        EXPECT_EQ(wrong.load(), 0u) << w << "x" << h << " phi " << phi << " avx2 " << avx2;
      }
    }
  }
}

// The terrain's slopes are the double-precision central differences (one-
// sided at the edges) to single precision.
TEST(HorizonBlocks, TerrainSlopesAreCentralDifferences) {
  const Heightfield field = roughTerrain(23, 19, true);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  double worst = 0;
  for (int row = 0; row < field.height; ++row) {
    for (int col = 0; col < field.width; ++col) {
      const int west = std::max(col - 1, 0), east = std::min(col + 1, field.width - 1);
      const int north = std::max(row - 1, 0), south = std::min(row + 1, field.height - 1);
      const double dzdx = (double(field.at(east, row)) - field.at(west, row)) /
                          ((east - west) * field.cellSizeXAtRow(row));
      const double dzdy = (double(field.at(col, north)) - field.at(col, south)) /
                          ((south - north) * field.cellSizeYM);
      worst = std::max({worst, std::abs(terrain.slopeEastAt(col, row) - dzdx),
                        std::abs(terrain.slopeNorthAt(col, row) - dzdy)});
    }
  }
  EXPECT_LT(worst, 1e-5);
  // A field one texel wide or tall has no slope across it.
  const Heightfield line = roughTerrain(1, 5, false);
  const BakeTerrain lineTerrain = prepareBakeTerrain(line);
  EXPECT_EQ(lineTerrain.slopeEastAt(0, 2), 0.0f);
  EXPECT_NE(lineTerrain.slopeNorthAt(0, 2), 0.0f);
}

// The same for whole bakes: opposed and single azimuths, with the sky view
// factor, clamped edges and curvature, and within a short distance limit.
TEST(HorizonBlocks, Avx2AndScalarBakesAgree) {
  if (!cpuHasAvx2()) GTEST_SKIP() << "no AVX2 on this CPU";
  const Heightfield field = roughTerrain(70, 53, true);
  BakeOptions opposed;
  opposed.azimuths = 32;
  BakeOptions single;
  single.azimuths = 15;
  single.clampEdge = true;
  single.curvature = true;
  single.skyViewFactor = true;
  BakeOptions limited = single;
  limited.azimuths = 32;
  limited.maxDistanceM = 700;
  for (const BakeOptions& o : {opposed, single, limited}) {
    BakeResult scalar, avx2;
    {
      const Avx2Allowed allowed(false);
      scalar = bakeApertures(field, o);
    }
    {
      const Avx2Allowed allowed(true);
      avx2 = bakeApertures(field, o);
    }
    // Bit for bit (memcmp: no null pointers, even for the empty SVF).
    const auto sameBits = [](const std::vector<float>& a, const std::vector<float>& b) {
      return a.size() == b.size() &&
             (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
    };
    EXPECT_FALSE(scalar.aperture.texels.empty());
    EXPECT_TRUE(sameBits(scalar.aperture.texels, avx2.aperture.texels)) << o.azimuths;
    EXPECT_EQ(scalar.skyViewFactor.empty(), !o.skyViewFactor);
    EXPECT_TRUE(sameBits(scalar.skyViewFactor, avx2.skyViewFactor)) << o.azimuths;
  }
}

// The hull stacks of a group's lines lie an odd number of cache lines apart
// whatever the length (at a power of two they shared a few L1 sets), with
// room for a point per step.
TEST(HorizonBlocks, HullStacksLieAnOddNumberOfCacheLinesApart) {
  for (const int length : {1, 7, 8, 255, 256, 1000, 1024, 2048, 16385}) {
    const size_t bytes =
        sizeof(detail::HullPointF) * static_cast<size_t>(detail::hullStride(length));
    EXPECT_GE(detail::hullStride(length), length);
    EXPECT_EQ(bytes % 64, 0u) << length;
    EXPECT_EQ(bytes / 64 % 2, 1u) << length;
  }
}

// A bake without the aperture map (BakeOptions::apertureMap, aal-bake's GIS
// rasters alone) sums the visible solid angle on its own: the same bits as
// the map's fourth sum, on either path, with every sweep the bake takes.
TEST(HorizonBlocks, BakesWithoutTheMapGiveTheSameRasters) {
  const auto sameBits = [](const std::vector<float>& a, const std::vector<float>& b) {
    return a.size() == b.size() && !a.empty() &&
           std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
  };
  BakeOptions opposed;
  opposed.azimuths = 32;
  BakeOptions single = opposed;
  single.azimuths = 15;  // odd: no opposed pass
  single.clampEdge = true;
  single.curvature = true;
  BakeOptions scanned = opposed;
  scanned.maxDistanceM = 700;
  BakeOptions runs = opposed;  // too long for the block sweep's scan: its runs
  runs.maxDistanceM = 30000;
  for (const bool geographic : {false, true}) {
    const Heightfield field = roughTerrain(70, 53, geographic);
    for (BakeOptions o : {opposed, single, scanned, runs}) {
      o.skyViewFactor = o.visibleFraction = true;
      for (const bool avx2 : {false, true}) {
        const Avx2Allowed allowed(avx2);
        o.apertureMap = true;
        const BakeResult map = bakeApertures(field, o);
        o.apertureMap = false;
        const BakeResult gis = bakeApertures(field, o);
        const std::string where = std::string(geographic ? "geographic" : "uniform") +
                                  ", azimuths " + std::to_string(o.azimuths) + ", limit " +
                                  std::to_string(o.maxDistanceM) + (avx2 ? ", AVX2" : "");
        EXPECT_TRUE(gis.aperture.texels.empty()) << where;
        EXPECT_EQ(gis.aperture.width, 0) << where;
        ASSERT_EQ(map.visibleFraction.size(), field.texelCount()) << where;
        EXPECT_TRUE(sameBits(map.visibleFraction, gis.visibleFraction)) << where;
        EXPECT_TRUE(sameBits(map.skyViewFactor, gis.skyViewFactor)) << where;
        // The sky-view factor alone, which takes no slopes.
        o.visibleFraction = false;
        EXPECT_TRUE(sameBits(map.skyViewFactor, bakeApertures(field, o).skyViewFactor)) << where;
        o.visibleFraction = true;
        // The map's arc length r holds the same share: 1 - cos r.
        double worst = 0;
        for (size_t i = 0; i < field.texelCount(); ++i) {
          const double r = map.aperture.texels[4 * i + 3];
          worst = std::max(worst, std::abs(map.visibleFraction[i] - (1.0 - std::cos(r))));
        }
        EXPECT_LT(worst, 1e-6) << where;
      }
    }
  }
}

}  // namespace
}  // namespace aal
