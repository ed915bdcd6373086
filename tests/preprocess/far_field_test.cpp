// The far field of tiled bakes without a max distance (docs/baking.md, "Far
// field"): the height pyramid against brute force, the near sweep of a
// window, and tiled bakes against the whole-DEM bake with unlimited
// distance, where a high ridge beyond the halo shadows the far tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "aperture/preprocess/far_horizon.h"
#include "aperture/preprocess/height_pyramid.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/tiled_bake.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

Heightfield fbm(int width, int height, double amplitudeM, uint64_t seed = 5) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 30;
  s.seed = seed;
  s.amplitudeM = amplitudeM;
  s.featureSizeTexels = 48;
  s.octaves = 6;
  return makeSyntheticTerrain(s);
}

// Makes `field` a geographic grid: its rows' east-west cells grow evenly
// from `northM` (first row) to `southM` (last), so columns drift with the row.
void makeGeographic(Heightfield& field, double northM, double southM) {
  field.rowCellSizeXM.resize(static_cast<size_t>(field.height));
  for (int row = 0; row < field.height; ++row) {
    field.rowCellSizeXM[static_cast<size_t>(row)] =
        northM + (southM - northM) * row / (field.height - 1);
  }
  field.cellSizeXM = field.rowCellSizeXM[static_cast<size_t>(field.height / 2)];
}

// A block visitor that keeps each texel's tangent in `out` (window indices).
auto keepTangents(std::vector<float>& out) {
  return [&out](const HorizonBlock& b) {
    for (int j = 0; j < b.count; ++j) out[b.firstTexel + j * b.stride] = b.tanHorizon[j];
  };
}

// Where a pyramid's levels live: memory, or a file no folder names (empty:
// memory).
std::vector<std::string> storages() {
  return {std::string(), fs::temp_directory_path().string()};
}

// Every level's maximum is the largest texel of its block (so never below
// any texel it covers): brute force over the blocks, on a size that leaves
// partial blocks at both edges, in memory and in a file.
TEST(HeightPyramid, MaximaOfEveryBlock) {
  const Heightfield field = fbm(75, 46, 800);
  for (const std::string& folder : storages()) {
    for (const int baseShift : {0, 2}) {
      HeightPyramid pyramid(field.width, field.height, baseShift, folder);
      pyramid.addRows(field.z.data(), field.height);
      EXPECT_EQ(pyramid.inFile(), !folder.empty());
      EXPECT_EQ(pyramid.baseShift(), baseShift);
      const HeightPyramid::Level& top = pyramid.level(pyramid.coarsestShift());
      EXPECT_EQ(top.width, 1);
      EXPECT_EQ(top.height, 1);
      for (int shift = pyramid.baseShift(); shift <= pyramid.coarsestShift(); ++shift) {
        const HeightPyramid::Level& level = pyramid.level(shift);
        const std::vector<float> maxima = pyramid.levelMax(shift);
        const int size = 1 << shift;
        ASSERT_EQ(level.width, (field.width + size - 1) / size);
        ASSERT_EQ(level.height, (field.height + size - 1) / size);
        for (int by = 0; by < level.height; ++by) {
          for (int bx = 0; bx < level.width; ++bx) {
            float max = -std::numeric_limits<float>::infinity();
            for (int row = by * size; row < std::min(field.height, (by + 1) * size); ++row) {
              for (int col = bx * size; col < std::min(field.width, (bx + 1) * size); ++col) {
                max = std::max(max, field.at(col, row));
              }
            }
            ASSERT_EQ(maxima[static_cast<size_t>(by) * level.width + bx], max)
                << "shift " << shift << " block " << bx << "," << by << " in '" << folder << "'";
          }
        }
        // A rectangle of a level is the level's blocks.
        if (level.width > 2 && level.height > 2) {
          std::vector<float> part(static_cast<size_t>(level.width - 2) * 2);
          pyramid.readBlocks(shift, 1, 1, level.width - 2, 2, part.data());
          for (int y = 0; y < 2; ++y)
            for (int x = 0; x < level.width - 2; ++x)
              EXPECT_EQ(part[static_cast<size_t>(y) * (level.width - 2) + x],
                        maxima[static_cast<size_t>(1 + y) * level.width + 1 + x]);
        }
      }
      std::vector<float> one(1);
      EXPECT_THROW(
          pyramid.readBlocks(baseShift, pyramid.level(baseShift).width, 0, 1, 1, one.data()),
          std::out_of_range);
    }
  }
}

// The file has no name: nothing is left in its folder, during or after.
TEST(HeightPyramid, TheFileLeavesNothingInItsFolder) {
  const Heightfield field = fbm(75, 46, 800);
  test::TempDir dir;
  {
    HeightPyramid pyramid(field.width, field.height, 1, dir.path().string());
    pyramid.addRows(field.z.data(), field.height);
    EXPECT_TRUE(fs::is_empty(dir.path()));
  }
  EXPECT_TRUE(fs::is_empty(dir.path()));
  EXPECT_THROW(HeightPyramid(field.width, field.height, 1, (dir.path() / "missing").string()),
               std::runtime_error);
}

// A bake reading windows keeps the pyramid on the output's file system: in
// the folder once it exists, before that in its parent; where asked.
TEST(HeightPyramid, TheFileGoesBesideTheTiles) {
  test::TempDir dir;
  const std::string folder = (dir.path() / "tiles").string();
  TiledBakeOptions tiled;
  EXPECT_EQ(fs::path(tiledBakePyramidFolder(tiled, folder)), dir.path());
  fs::create_directory(folder);
  EXPECT_EQ(fs::path(tiledBakePyramidFolder(tiled, folder)), fs::path(folder));
  tiled.pyramidFolder = "/somewhere/else";
  EXPECT_EQ(tiledBakePyramidFolder(tiled, folder), "/somewhere/else");
}

void expectSamePyramid(const HeightPyramid& have, const HeightPyramid& want) {
  ASSERT_TRUE(have.complete());
  ASSERT_EQ(have.coarsestShift(), want.coarsestShift());
  for (int shift = want.baseShift(); shift <= want.coarsestShift(); ++shift) {
    EXPECT_EQ(have.levelMax(shift), want.levelMax(shift)) << "shift " << shift;
  }
}

// Rows handed over in bands of any size build the same pyramid.
TEST(HeightPyramid, BandsOfRowsBuildTheSamePyramid) {
  const Heightfield field = fbm(75, 46, 800);
  const HeightPyramid whole = buildHeightPyramid(field, 1);
  for (const std::string& folder : storages()) {
    HeightPyramid bands(field.width, field.height, 1, folder);
    for (int row = 0; row < field.height;) {
      const int rows = std::min(field.height - row, 1 + row % 7);
      EXPECT_FALSE(bands.complete());
      bands.addRows(field.z.data() + static_cast<size_t>(row) * field.width, rows);
      row += rows;
    }
    expectSamePyramid(bands, whole);
    EXPECT_THROW(bands.addRows(field.z.data(), 1), std::invalid_argument);
  }
}

// A pass split over threads or MPI ranks hands over whole block rows in any
// order: the same pyramid, bit for bit, as the rows in order, also when
// the DEM's height is not a multiple of the block (46 rows, blocks of 4 and
// 8: a last block row of 2 and 6 rows).
TEST(HeightPyramid, BlockRowsInAnyOrderBuildTheSamePyramid) {
  const Heightfield field = fbm(75, 46, 800);
  for (const std::string& folder : storages()) {
    for (int shift : {2, 3}) {
      SCOPED_TRACE(::testing::Message() << "shift " << shift << " in '" << folder << "'");
      const HeightPyramid whole = buildHeightPyramid(field, shift);
      const int block = 1 << shift;
      // Chunks of 1, 2 and 3 block rows, last chunk first.
      std::vector<std::pair<int, int>> chunks;  // first row, rows
      for (int row = 0, n = 1; row < field.height; row += n * block, n = n % 3 + 1) {
        chunks.emplace_back(row, std::min(n * block, field.height - row));
      }
      std::reverse(chunks.begin(), chunks.end());
      HeightPyramid parts(field.width, field.height, shift, folder);
      for (const auto& [row, rows] : chunks) {
        EXPECT_FALSE(parts.complete());
        parts.addBlockRows(row, field.z.data() + static_cast<size_t>(row) * field.width, rows);
      }
      expectSamePyramid(parts, whole);
      // Not whole block rows, or twice.
      HeightPyramid bad(field.width, field.height, shift, folder);
      EXPECT_THROW(bad.addBlockRows(1, field.z.data(), block), std::invalid_argument);
      EXPECT_THROW(bad.addBlockRows(0, field.z.data(), block + 1), std::invalid_argument);
      bad.addBlockRows(0, field.z.data(), block);
      EXPECT_THROW(bad.addBlockRows(0, field.z.data(), block), std::invalid_argument);
      EXPECT_THROW(bad.addRows(field.z.data(), 1), std::invalid_argument);
    }
  }
}

// The ranks of an MPI bake take the block rows other ranks made and build
// the coarser levels themselves: every level the same floats.
TEST(HeightPyramid, BlockRowsFromAnotherPyramidAreTheSame) {
  const Heightfield field = fbm(75, 46, 800);
  const HeightPyramid whole = buildHeightPyramid(field, 1);
  const std::vector<float> base = whole.levelMax(1);
  const int width = whole.level(1).width;
  ASSERT_EQ(whole.level(1).height, 23);
  for (const std::string& folder : storages()) {
    HeightPyramid copy(field.width, field.height, 1, folder);
    // Block rows 10-22 given, 0-9 made from their rows.
    copy.setBaseBlockRows(10, 13, base.data() + static_cast<size_t>(10) * width);
    EXPECT_FALSE(copy.complete());
    copy.addBlockRows(0, field.z.data(), 20);
    expectSamePyramid(copy, whole);
    // Filled once.
    EXPECT_THROW(copy.setBaseBlockRows(0, 1, base.data()), std::invalid_argument);
  }
}

// The march of a window's lines reads only blocks FarFieldWindow holds, and
// the same maxima as from the whole pyramid: from every start point where
// a line that reaches the tile can start (the tile and tileHalo around
// it), every azimuth, on a metric and a geographic grid (rows' cells from
// 21 to 37 m, so that columns drift with the row), for reaches that start
// on the base level and above it. A small tile at a short reach holds a
// small part of the pyramid.
TEST(FarField, WindowsHoldWhatTheLinesReadAndLittleMore) {
  Heightfield field = fbm(900, 700, 900);
  for (const bool geographic : {false, true}) {
    if (geographic) makeGeographic(field, 21.0, 37.0);
    for (const double reachCells : {16.0, 40.0, 130.0}) {
      FarFieldOptions options;
      options.nearReachM = reachCells * 30.0;
      double largest = field.cellSizeYM;
      for (int row = 0; row < field.height; ++row)
        largest = std::max(largest, field.cellSizeXAtRow(row));
      const HeightPyramid pyramid = buildHeightPyramid(field, farFieldBaseShift(options, largest));
      const FarField far{&pyramid, options};
      const BakeTerrain whole = prepareBakeTerrain(field);
      const FarFieldWindow all(far, whole);
      for (const TexelWindow& tile : {TexelWindow{0, 0, 40, 40}, TexelWindow{430, 300, 40, 40},
                                      TexelWindow{860, 640, 40, 60}}) {
        SCOPED_TRACE(::testing::Message() << "geographic " << geographic << ", reach " << reachCells
                                          << " cells, tile at " << tile.col << "," << tile.row);
        const BakeTerrain part = prepareBakeTerrain(field, tile);
        const FarFieldWindow held(far, part);
        EXPECT_LE(held.bytes(), all.bytes());
        if (reachCells == 16.0) {
          EXPECT_LT(held.bytes(), all.bytes() / 4);
        }
        const int halo = detail::stepsCovering(part, options.nearReachM) + 40 + 3;
        for (int a = 0; a < 16; ++a) {
          const double phi = (a + 0.3) * 2 * std::numbers::pi / 16;
          const FarLineMarch fromHeld(held, part, phi), fromAll(all, whole, phi);
          std::vector<float> d1, h1, d2, h2;
          for (int row = tile.row - halo; row < tile.row + tile.height + halo; row += 7) {
            for (int col = tile.col - halo; col < tile.col + tile.width + halo; col += 7) {
              if (col < 0 || row < 0 || col >= field.width || row >= field.height) continue;
              ASSERT_NO_THROW(fromHeld.march(col + 0.4, row - 0.3, d1, h1));
              fromAll.march(col + 0.4, row - 0.3, d2, h2);
              ASSERT_EQ(d1, d2);
              ASSERT_EQ(h1, h2);
            }
          }
        }
      }
    }
  }
}

// A window's lines walked from windowReachM before it: each texel's horizon
// covers at least that distance (no lower than the horizon within it) and
// at most its whole line (no higher than the unlimited one).
TEST(FarField, WindowReachCoversTheReachAndNoMore) {
  const Heightfield field = fbm(120, 90, 900);
  const TexelWindow window{50, 30, 30, 25};
  const BakeTerrain whole = prepareBakeTerrain(field);
  const BakeTerrain part = prepareBakeTerrain(field, window);
  const double reach = 20 * 30.0;
  for (const bool clampEdge : {false, true}) {
    HorizonSweepOptions limited, reaching, unlimited;
    limited.maxDistanceM = reach;
    reaching.windowReachM = reach;
    for (HorizonSweepOptions* o : {&limited, &reaching, &unlimited}) o->clampEdge = clampEdge;
    size_t aboveLimited = 0;
    for (int a = 0; a < 24; ++a) {
      const double phi = a * 2 * std::numbers::pi / 24;
      std::vector<double> near(window.texelCount()), within(window.texelCount()),
          all(field.texelCount());
      sweepHorizons(part, phi, reaching, [&](size_t i, double t) { near[i] = t; });
      sweepHorizons(part, phi, limited, [&](size_t i, double t) { within[i] = t; });
      sweepHorizons(whole, phi, unlimited, [&](size_t i, double t) { all[i] = t; });
      for (int row = window.row; row < window.row + window.height; ++row) {
        for (int col = window.col; col < window.col + window.width; ++col) {
          const size_t i = part.windowIndex(col, row);
          ASSERT_GE(near[i], within[i] - 1e-9) << col << "," << row << " azimuth " << a;
          ASSERT_LE(near[i], all[field.index(col, row)] + 1e-9) << col << "," << row;
          if (near[i] > within[i] + 1e-6) ++aboveLimited;
        }
      }
    }
    // The walk reaches past the limit for texels deep in the window.
    EXPECT_GT(aboveLimited, 0u);
  }
}

// The block sweep of a window (sweepWindowHorizonBlocks, what the bake
// runs) visits every texel of the window once, with the tangents of the
// general sweep with the same reach (to single precision), on the AVX2 and
// the scalar path, with and without curvature.
TEST(FarField, WindowBlocksEqualTheWindowSweep) {
  const Heightfield field = fbm(130, 95, 900);
  const TexelWindow window{47, 31, 41, 29};
  const BakeTerrain part = prepareBakeTerrain(field, window);
  for (const bool avx2 : {true, false}) {
    setHorizonAvx2Allowed(avx2);
    for (const double curvature : {0.0, 1e-6}) {
      HorizonSweepOptions o;
      o.windowReachM = 17 * 30.0;
      o.curvature = curvature;
      for (int a = 0; a < 24; ++a) {
        const double phi = a * 2 * std::numbers::pi / 24;
        std::vector<double> general(window.texelCount());
        std::vector<float> blocks(window.texelCount(), NAN);
        std::vector<int> visits(window.texelCount(), 0);
        sweepHorizons(part, phi, o, [&](size_t i, double t) { general[i] = t; });
        sweepWindowHorizonBlocks(part, phi, o, [&](const HorizonBlock& b) {
          for (int j = 0; j < b.count; ++j) {
            const size_t i = b.firstTexel + j * b.stride;
            ASSERT_LT(i, blocks.size());
            blocks[i] = b.tanHorizon[j];
            ++visits[i];
          }
        });
        for (size_t i = 0; i < general.size(); ++i) {
          ASSERT_EQ(visits[i], 1) << "texel " << i << " azimuth " << a;
          if (general[i] <= kNoHorizonTangent) {
            EXPECT_LE(blocks[i], kNoHorizonTangent) << "texel " << i << " azimuth " << a;
          } else {
            EXPECT_NEAR(blocks[i], general[i], 1e-4 * (1 + std::abs(general[i])))
                << "texel " << i << " azimuth " << a << (avx2 ? " avx2" : " scalar");
          }
        }
      }
    }
  }
  setHorizonAvx2Allowed(true);
}

// Each line of a window's sweep starts the reach before the first step at
// which it passes beside a window texel (SweepLayout::lineStart), found
// here by trying every texel: lines that cross the window's side start
// there, not the reach before the window's first step.
TEST(FarField, EachLineStartsTheReachBeforeItsFirstWindowTexel) {
  const Heightfield field = fbm(90, 70, 300);
  const TexelWindow window{31, 17, 23, 19};
  const BakeTerrain part = prepareBakeTerrain(field, window);
  const double reachM = 9 * 30.0;
  const int reach = detail::stepsCovering(part, reachM);
  int later = 0;
  for (int a = 0; a < 24; ++a) {
    const double phi = a * 2 * std::numbers::pi / 24 + 0.1;
    const detail::SweepLayout layout =
        detail::makeSweepLayout(part, std::cos(phi), std::sin(phi), reachM);
    for (int line = layout.firstLine; line <= layout.lastLine; ++line) {
      int first = layout.endStep;  // texel (k, m) lies between lines m - offset - 1 and m - offset
      for (int k = layout.visitStep; k < layout.endStep && first == layout.endStep; ++k) {
        for (int m = layout.minorBegin; m < layout.minorEnd; ++m) {
          const int c = m - layout.floorOffset[k];
          if (line == c || line == c - 1) first = k;
        }
      }
      const int expected = first == layout.endStep ? layout.endStep : std::max(0, first - reach);
      ASSERT_EQ(layout.startOf(line), expected) << "azimuth " << a << ", line " << line;
      if (expected > layout.firstStep && expected < layout.endStep) ++later;
    }
  }
  EXPECT_GT(later, 200);  // the oblique sweeps' lines across the window's sides
}

// Both azimuths of a window in one pass (sweepOpposedHorizonBlocks with
// windowReachM): each texel visited once, with the tangents of each
// azimuth's own window sweep bit for bit, far field or not, open and
// clamped edges, on a metric and a geographic grid, the AVX2 and scalar
// walks; every azimuth pair of 24 (at 45 degrees the lines do not pair).
TEST(FarField, OpposedWindowSweepEqualsTheTwoWindowSweeps) {
  Heightfield field = fbm(160, 120, 900);
  const TexelWindow window{57, 31, 45, 37};
  FarFieldOptions options;
  options.nearReachM = 17 * 30.0;
  for (const bool geographic : {false, true}) {
    if (geographic) makeGeographic(field, 24.0, 33.0);
    const BakeTerrain part = prepareBakeTerrain(field, window);
    const HeightPyramid pyramid = buildHeightPyramid(field, 0);
    const FarFieldWindow far(FarField{&pyramid, options}, part);
    for (const bool avx2 : {true, false}) {
      setHorizonAvx2Allowed(avx2);
      for (const auto& [withFar, clampEdge] :
           {std::pair{false, false}, std::pair{true, false}, std::pair{true, true}}) {
        HorizonSweepOptions o;
        o.windowReachM = options.nearReachM;
        o.curvature = 1e-6;
        o.clampEdge = clampEdge;
        const FarFieldWindow* farWindow = withFar ? &far : nullptr;
        int paired = 0;
        for (int a = 0; a < 12; ++a) {
          SCOPED_TRACE(::testing::Message()
                       << "geographic " << geographic << ", avx2 " << avx2 << ", far " << withFar
                       << ", clamped " << clampEdge << ", azimuth " << a);
          const double phi = a * 2 * std::numbers::pi / 24, opposite = phi + std::numbers::pi;
          std::vector<float> one(window.texelCount(), NAN), other(window.texelCount(), NAN);
          sweepWindowHorizonBlocks(part, phi, o, keepTangents(one), farWindow);
          sweepWindowHorizonBlocks(part, opposite, o, keepTangents(other), farWindow);
          std::vector<float> both(window.texelCount(), NAN), bothOther(window.texelCount(), NAN);
          std::vector<int> visits(window.texelCount(), 0);
          if (!sweepOpposedHorizonBlocks(
                  part, phi, opposite, o,
                  [&](const HorizonBlock& b) {
                    for (int j = 0; j < b.count; ++j) {
                      const size_t i = b.firstTexel + j * b.stride;
                      ASSERT_LT(i, both.size());
                      both[i] = b.tanHorizon[j];
                      bothOther[i] = b.tanOpposite[j];
                      ++visits[i];
                    }
                  },
                  farWindow)) {
            continue;
          }
          ++paired;
          for (size_t i = 0; i < both.size(); ++i) {
            ASSERT_EQ(visits[i], 1) << "texel " << i;
            ASSERT_EQ(both[i], one[i]) << "texel " << i;
            ASSERT_EQ(bothOther[i], other[i]) << "texel " << i;
          }
        }
        EXPECT_GE(paired, 8);
      }
    }
  }
  setHorizonAvx2Allowed(true);
}

// A window's lines seeded with the far field (sweepWindowHorizonBlocks
// with a FarField) against the same lines walked over the whole DEM
// (sweepHorizonBlocks), at the window's texels: block maxima lower a
// horizon rarely and little, and the far field recovers nearly all of what
// the near sweep alone misses. Open edges flat and curved, clamped
// edges curved, the AVX2 and scalar walks.
TEST(FarField, SeededLinesSeeNearlyAllTheNearSweepMisses) {
  const Heightfield field = fbm(300, 220, 900);
  const TexelWindow window{120, 70, 90, 75};
  const BakeTerrain whole = prepareBakeTerrain(field);
  const BakeTerrain part = prepareBakeTerrain(field, window);
  FarFieldOptions options;
  options.nearReachM = 40 * 30.0;
  const HeightPyramid pyramid =
      buildHeightPyramid(field, farFieldBaseShift(options, field.cellSizeXM));
  const FarField far{&pyramid, options};
  const FarFieldWindow farWindow(far, part);
  for (const bool avx2 : {true, false}) {
    setHorizonAvx2Allowed(avx2);
    for (const auto& [curvature, clampEdge] :
         {std::pair{0.0, false}, std::pair{1e-6, false}, std::pair{1e-6, true}}) {
      HorizonSweepOptions o;
      o.curvature = curvature;
      o.clampEdge = clampEdge;
      double seededError = 0, nearError = 0, largestUnder = 0;
      size_t counted = 0, lower = 0;
      for (int a = 0; a < 16; ++a) {
        const double phi = (a + 0.3) * 2 * std::numbers::pi / 16;
        std::vector<float> reference(window.texelCount()), seeded(window.texelCount()),
            nearOnly(window.texelCount());
        sweepHorizonBlocks(whole, phi, o, [&](const HorizonBlock& b) {
          for (int j = 0; j < b.count; ++j) {
            const size_t i = b.firstTexel + j * b.stride;
            const int col = static_cast<int>(i % field.width),
                      row = static_cast<int>(i / field.width);
            if (window.containsColumn(col) && window.containsRow(row)) {
              reference[window.index(col, row)] = b.tanHorizon[j];
            }
          }
        });
        HorizonSweepOptions windowed = o;
        windowed.windowReachM = options.nearReachM;
        sweepWindowHorizonBlocks(part, phi, windowed, keepTangents(seeded), &farWindow);
        HorizonSweepOptions open = windowed;
        open.clampEdge = false;
        sweepWindowHorizonBlocks(part, phi, open, keepTangents(nearOnly));
        for (size_t i = 0; i < reference.size(); ++i) {
          if (reference[i] <= kNoHorizonTangent) continue;
          const double under = reference[i] - seeded[i];
          if (under > 1e-4 * (1 + std::abs(reference[i]))) ++lower;
          largestUnder = std::max(largestUnder, under);
          seededError += seeded[i] - reference[i];
          nearError += reference[i] - std::max(nearOnly[i], kNoHorizonTangent);
          ++counted;
        }
      }
      SCOPED_TRACE(::testing::Message()
                   << "curvature " << curvature << ", clamped " << clampEdge << ": seeded "
                   << seededError / counted << ", near only " << nearError / counted
                   << ", lower at " << lower << " of " << counted << " by up to " << largestUnder);
      // The near sweep alone misses far terrain at this reach; the far
      // field's blocks overshoot by less than 15 % of that (0.07-0.09 here).
      EXPECT_GT(nearError / counted, 1e-3);
      EXPECT_LT(seededError, 0.15 * nearError);
      // Samples every half block may pass by a block's corner, or miss the
      // neighbour across the line that the line's height blends in: a
      // horizon comes out lower at a few texels, by little (0.1-0.2 % of
      // them, by up to 0.0027 here).
      EXPECT_LT(lower, counted / 200);
      EXPECT_LT(largestUnder, 0.005);
    }
  }
  setHorizonAvx2Allowed(true);
}

// Mean and 99th percentile of |visible fraction difference| and mean
// bent-normal angle (degrees) of `map` against `reference`, over `window`
// of the reference (the whole map when empty).
struct Differences {
  double visibleMean = 0, visibleP99 = 0, angleMean = 0;
};

Differences differences(const ApertureMap& reference, const ApertureMap& map,
                        TexelWindow window = {}) {
  if (window.width == 0) window = TexelWindow{0, 0, reference.width, reference.height};
  std::vector<double> visible;
  double angles = 0.0;
  for (int row = window.row; row < window.row + window.height; ++row) {
    for (int col = window.col; col < window.col + window.width; ++col) {
      const size_t i = static_cast<size_t>(row) * reference.width + col;
      visible.push_back(std::abs(reference.visibleFraction(i) - map.visibleFraction(i)));
      const float* a = &reference.texels[4 * i];
      const float* b = &map.texels[4 * i];
      const double dot = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
      const double lengths =
          std::sqrt((double(a[0]) * a[0] + double(a[1]) * a[1] + double(a[2]) * a[2]) *
                    (double(b[0]) * b[0] + double(b[1]) * b[1] + double(b[2]) * b[2]));
      angles += std::acos(std::clamp(dot / lengths, -1.0, 1.0)) * 180.0 / std::numbers::pi;
    }
  }
  Differences d;
  for (double v : visible) d.visibleMean += v;
  d.visibleMean /= visible.size();
  std::sort(visible.begin(), visible.end());
  d.visibleP99 = visible[static_cast<size_t>(0.99 * (visible.size() - 1))];
  d.angleMean = angles / visible.size();
  return d;
}

// Low hills at 30 m cells, and a ridge 600 m high (a Gaussian across, 20
// cells wide, slopes up to ~0.6) along the whole north-south extent 175
// cells and more east of the western tiles: those lie far beyond the near
// reach (64 cells), so only the far field sees it.
Heightfield ridgeField() {
  Heightfield field = fbm(512, 128, 60);
  for (int row = 0; row < field.height; ++row) {
    for (int col = 0; col < field.width; ++col) {
      const double across = (col - 430.5) / 20.0;
      field.z[field.index(col, row)] +=
          static_cast<float>(600.0 * std::exp(-0.5 * across * across));
    }
  }
  return field;
}

// The default far field's proportions (a near reach of 128 cells, blocks
// 1/16 of their distance) at a smaller scale, on tiles of 64.
TiledBakeOptions farTiles() {
  TiledBakeOptions t;
  t.tileSize = 64;
  t.halfFloat = false;  // compared with the in-memory bake's floats
  t.farField.nearReachM = 64 * 30.0;
  return t;
}

BakeOptions unlimited(bool curvature = false) {
  BakeOptions o;
  o.azimuths = 32;
  o.curvature = curvature;
  return o;
}

// The tiled bake without a max distance against the in-memory bake with
// unlimited distance: within the targets (docs/baking.md, "Far field") everywhere and on the
// western tiles, which the ridge shadows from beyond their halo. Without
// the far field (the near sweep alone, as a max distance of the reach)
// those tiles miss the ridge by far more than the targets.
TEST(FarField, TiledBakeSeesADistantRidgeBeyondTheHalo) {
  test::TempDir dir;
  const Heightfield field = ridgeField();
  // Open edges flat and curved (the block sweep), clamped edges curved
  // (the general sweep and the far field's plateau beyond the edge).
  for (const auto& [curvature, clampEdge] :
       {std::pair{false, false}, std::pair{true, false}, std::pair{true, true}}) {
    BakeOptions o = unlimited(curvature);
    o.clampEdge = clampEdge;
    const ApertureMap reference = bakeApertures(field, o).aperture;
    const std::string folder =
        (dir.path() / ((curvature ? "curved" : "flat") + std::string(clampEdge ? "-clamp" : "")))
            .string();
    const TiledBakeSummary summary = bakeTiled(field, o, farTiles(), folder);
    EXPECT_EQ(summary.baked, 8 * 2);
    const ApertureMap tiled = readApertureMap(folder);
    const TexelWindow west{0, 0, 256, field.height};
    for (const TexelWindow& window : {TexelWindow{}, west}) {
      const Differences d = differences(reference, tiled, window);
      SCOPED_TRACE(::testing::Message()
                   << "curvature " << curvature << ", window width " << window.width << ": mean "
                   << d.visibleMean << ", p99 " << d.visibleP99 << ", angle " << d.angleMean);
      EXPECT_LE(d.visibleMean, 0.002);
      EXPECT_LE(d.visibleP99, 0.01);
      EXPECT_LE(d.angleMean, 0.2);
    }
    // The near sweep alone misses the ridge in the west by more than twice
    // the targets.
    BakeOptions nearOnly = o;
    nearOnly.maxDistanceM = farTiles().farField.nearReachM;
    const ApertureMap near = bakeApertures(field, nearOnly).aperture;
    const Differences missed = differences(reference, near, west);
    EXPECT_GT(missed.visibleMean, 2 * 0.002);
    EXPECT_GT(missed.angleMean, 2 * 0.2);
  }
}

// Block maxima never put the far horizon below the terrain's: the
// far-field bake sees no more sky than the in-memory one anywhere, but for
// 0.0002. (Without the two blocks that each line's walk adds to the near
// reach, farFieldWalkReachM, 2 texels of the ridge's crest read 0.00024
// more: a first far block reaching back inside the near reach.)
TEST(FarField, MaximaNeverSeeMoreSkyThanTheTerrainAllows) {
  test::TempDir dir;
  const Heightfield field = ridgeField();
  const BakeOptions o = unlimited();
  const ApertureMap reference = bakeApertures(field, o).aperture;
  bakeTiled(field, o, farTiles(), (dir.path() / "tiles").string());
  const ApertureMap tiled = readApertureMap((dir.path() / "tiles").string());
  size_t moreSky = 0;
  for (size_t i = 0; i < reference.texelCount(); ++i) {
    if (tiled.visibleFraction(i) > reference.visibleFraction(i) + 2e-4) ++moreSky;
  }
  EXPECT_EQ(moreSky, 0u);
}

// The far-field bake records its method; a folder of a bake with a max
// distance (every tiled bake before the far field) is another bake's.
TEST(FarField, FoldersRecordTheFarFieldAndRefuseOtherBakes) {
  test::TempDir dir;
  const Heightfield field = fbm(64, 48, 300);
  TiledBakeOptions t = farTiles();
  const std::string folder = (dir.path() / "tiles").string();
  bakeTiled(field, unlimited(), t, folder);
  const ApertureTileIndex index = readApertureTileIndex(folder);
  EXPECT_EQ(index.map.info.method, farFieldMethod(t.farField));
  EXPECT_EQ(index.map.info.maxDistanceM, 0.0);
  EXPECT_NE(index.map.info.method.find("far-field(max, reach 1920 m, lines, blocks 1/16)"),
            std::string::npos)
      << index.map.info.method;
  // Other far-field options or a max distance: another bake.
  t.farField.resolution = 8;
  EXPECT_THROW(bakeTiled(field, unlimited(), t, folder), InputError);
  BakeOptions limited = unlimited();
  limited.maxDistanceM = 300;
  EXPECT_THROW(bakeTiled(field, limited, farTiles(), folder), InputError);
  const std::string old = (dir.path() / "old").string();
  bakeTiled(field, limited, farTiles(), old);
  EXPECT_THROW(bakeTiled(field, unlimited(), farTiles(), old), InputError);
}

// Interrupted past half way and run again, a far-field bake keeps its
// finished tiles and ends equal, bit for bit, to one uninterrupted bake.
TEST(FarField, InterruptedBakeResumes) {
  test::TempDir dir;
  const Heightfield field = ridgeField();
  BakeOptions o = unlimited();
  const std::string reference = (dir.path() / "reference").string();
  bakeTiled(field, o, farTiles(), reference);
  const std::string folder = (dir.path() / "tiles").string();
  std::atomic<bool> cancel{false};
  o.cancel = &cancel;
  o.progress = [&](double fraction) {
    if (fraction > 0.5) cancel = true;
  };
  EXPECT_THROW(bakeTiled(field, o, farTiles(), folder), BakeCancelled);
  EXPECT_FALSE(fs::exists(fs::path(folder) / "index.txt"));
  cancel = false;
  o.progress = nullptr;
  const TiledBakeSummary summary = bakeTiled(field, o, farTiles(), folder);
  EXPECT_EQ(summary.tiles, 16);
  EXPECT_GE(summary.resumed, 8);
  EXPECT_EQ(summary.baked + summary.resumed, 16);
  EXPECT_EQ(readApertureMap(folder).texels, readApertureMap(reference).texels);
}

}  // namespace
}  // namespace aal
