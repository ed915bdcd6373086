// Tiles baked from windows of the DEM (a tile and tileHalo around it, in
// rows and in columns): equal bit for bit to the tiles baked from the whole
// DEM, the halo holds every read of the sweeps in both directions, and the
// window reader slides along a tile row reading only the new columns.
#include "aperture/preprocess/tile_window_reader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/far_horizon.h"
#include "aperture/preprocess/height_pyramid.h"
#include "aperture/preprocess/tiled_bake.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

// fBm at 30 m cells, 600 m of relief. 150 x 110 in tiles of 24 leaves tiles
// of 6 columns at the right and of 14 rows at the bottom.
Heightfield fbmField(int width = 150, int height = 110) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 30;
  s.seed = 23;
  s.featureSizeTexels = 30;
  s.octaves = 5;
  return makeSyntheticTerrain(s);
}

// The same on a geographic grid far north: rows of different x spacing
// (~11 % from the southern to the northern edge).
Heightfield geographicField() {
  Heightfield field = fbmField();
  field.rowCellSizeXM.resize(static_cast<size_t>(field.height));
  for (int row = 0; row < field.height; ++row) {
    const double latDeg = 62.0 - row * 0.03;
    field.rowCellSizeXM[static_cast<size_t>(row)] =
        60.0 * std::cos(latDeg * std::numbers::pi / 180.0);
  }
  field.cellSizeXM = field.rowCellSizeXM[static_cast<size_t>(field.height / 2)];
  return field;
}

// Bit for bit (NaN payloads and signed zeros too). Empty vectors are equal
// without memcmp, whose null pointers would be undefined behaviour.
bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() &&
         (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0);
}

bool sameBits(const BakeResult& a, const BakeResult& b) {
  return sameBits(a.aperture.texels, b.aperture.texels) &&
         sameBits(a.skyViewFactor, b.skyViewFactor);
}

// A bake of `field`'s tiles: the options, and the far field when there is
// no max distance (its pyramid built from the whole field).
struct TileBake {
  BakeOptions bake;
  TiledBakeOptions tiled;
  std::optional<HeightPyramid> pyramid;
  FarField far;

  TileBake(const Heightfield& field, const BakeOptions& o, int tileSize, double nearReachM) {
    bake = o;
    tiled.tileSize = tileSize;
    tiled.farField.nearReachM = nearReachM;
    if (!(o.maxDistanceM > 0.0)) {
      pyramid.emplace(buildHeightPyramid(field, tiledBakePyramidShift(field, tiled)));
      far = FarField{&*pyramid, resolvedFarField(field, tiled)};
      bake.farField = &far;
    }
  }
  TileBake(const TileBake&) = delete;
};

BakeOptions options(double maxDistanceM, bool clampEdge, bool curvature) {
  BakeOptions o;
  o.azimuths = 20;  // not a multiple of 8: lines at every kind of slope
  o.maxDistanceM = maxDistanceM;
  o.clampEdge = clampEdge;
  o.curvature = curvature;
  o.skyViewFactor = true;
  return o;
}

// Bakes every tile of `field` from its window (tileHalo around it) and from
// the whole field, and expects the same bits; the windows of the inner
// tiles must leave out rows and columns, or the test would test nothing.
void expectWindowsBakeTheWholeFieldsTiles(const Heightfield& field, const BakeOptions& o,
                                          double nearReachM = 300.0) {
  constexpr int kTile = 24;
  const TileBake tiles(field, o, kTile, nearReachM);
  const int halo = tileHalo(field, tiles.bake, tiles.tiled);
  bool partial = false;
  for (int row = 0; row < field.height; row += kTile) {
    for (int col = 0; col < field.width; col += kTile) {
      const TexelWindow tile{col, row, std::min(kTile, field.width - col),
                             std::min(kTile, field.height - row)};
      const TexelWindow read = tileReadWindow(field, halo, tile);
      partial = partial || (read.width < field.width && read.height < field.height &&
                            read.col > 0 && read.row > 0);
      const HeightWindow window = windowOf(field, read);
      EXPECT_TRUE(sameBits(bakeApertureWindow(window, tile, tiles.bake),
                           bakeApertureWindow(field, tile, tiles.bake)))
          << "tile at " << col << "," << row << ", halo " << halo;
    }
  }
  EXPECT_TRUE(partial) << "no tile's window left out both rows and columns";
}

TEST(TileWindow, WindowsBakeTheWholeFieldsTilesWithAMaxDistance) {
  expectWindowsBakeTheWholeFieldsTiles(fbmField(), options(150.0, false, false));
  expectWindowsBakeTheWholeFieldsTiles(fbmField(), options(250.0, true, true));
}

TEST(TileWindow, WindowsBakeTheWholeFieldsTilesWithTheFarField) {
  expectWindowsBakeTheWholeFieldsTiles(fbmField(), options(0.0, false, false));
  expectWindowsBakeTheWholeFieldsTiles(fbmField(), options(0.0, true, true), 450.0);
}

TEST(TileWindow, WindowsBakeTheWholeFieldsTilesOnAGeographicGrid) {
  expectWindowsBakeTheWholeFieldsTiles(geographicField(), options(300.0, true, false));
  expectWindowsBakeTheWholeFieldsTiles(geographicField(), options(0.0, false, true));
}

// The halo holds every read that counts, in rows and in columns: the whole
// field with every texel outside the tile's rows +- h (or columns +- h) set
// to a height no terrain has bakes the tile as the clean field does exactly
// when h is at least the sweeps' reach in that direction. Found for rows and
// columns by bisection, with the unlimited hull of the far field's near
// sweep (every sample read stays in a line's hull, so a poisoned one is
// seen): both within tileHalo, and equal, since lines advancing by rows
// drift in columns as far as lines advancing by columns drift in rows.
TEST(TileWindow, TheHaloHoldsEveryReadInRowsAndInColumnsAlike) {
  const Heightfield field = fbmField(180, 180);
  const TexelWindow tile{78, 78, 24, 24};
  for (const bool clampEdge : {false, true}) {
    SCOPED_TRACE(clampEdge ? "clamped edges (the general sweep)" : "open edges (the block sweep)");
    BakeOptions o = options(0.0, clampEdge, false);
    o.azimuths = 32;  // a multiple of 4: the azimuths map onto each other across the diagonal
    o.skyViewFactor = false;
    const TileBake tiles(field, o, tile.width, 300.0);
    const int halo = tileHalo(field, tiles.bake, tiles.tiled);
    const BakeResult clean = bakeApertureWindow(field, tile, tiles.bake);
    // Whether the tile bakes as from the clean field with everything
    // farther than `reach` from it across rows (or columns) poisoned.
    const auto holds = [&](int reach, bool rows) {
      Heightfield poisoned = field;
      for (int row = 0; row < field.height; ++row) {
        for (int col = 0; col < field.width; ++col) {
          const int at = rows ? row : col, first = rows ? tile.row : tile.col;
          const int side = rows ? tile.height : tile.width;
          if (at < first - reach || at >= first + side + reach) {
            poisoned.z[field.index(col, row)] = 50000.0f;
          }
        }
      }
      return sameBits(bakeApertureWindow(poisoned, tile, tiles.bake), clean);
    };
    int reachOf[2] = {0, 0};
    for (const bool rows : {true, false}) {
      ASSERT_TRUE(holds(halo, rows)) << (rows ? "rows" : "columns") << ", halo " << halo;
      ASSERT_FALSE(holds(0, rows)) << "the poison is never seen: the test tests nothing";
      int lo = 0, hi = halo;  // holds(hi), !holds(lo)
      while (hi - lo > 1) {
        const int mid = (lo + hi) / 2;
        (holds(mid, rows) ? hi : lo) = mid;
      }
      reachOf[rows ? 0 : 1] = hi;
    }
    std::printf("reach of the sweeps around a %dx%d tile (halo %d): %d rows, %d columns\n",
                tile.width, tile.height, halo, reachOf[0], reachOf[1]);
    EXPECT_LE(reachOf[0], halo);
    EXPECT_EQ(reachOf[0], reachOf[1]);
  }
}

// The reader gives each tile its window and, along a tile row, keeps what
// the next tile's window shares with the last: it reads only the new
// columns (counted through DemSource), and the heights are the DEM's.
TEST(TileWindow, TheReaderSlidesAlongATileRowReadingOnlyTheNewColumns) {
  test::TempDir dir;
  const Heightfield field = fbmField(200, 90);
  const fs::path path = dir.path() / "dem.tif";
  writeFloatGeoTiff(path.string(), field.width, field.height, field.z.data(),
                    test::testGeoReference(false));
  const DemSource source(path.string(), DemLoadOptions{});
  const Heightfield geometry = demGeometry(source, DemLoadOptions{});
  constexpr int kTile = 32, kHalo = 30;
  TileWindowReader reader(source, geometry, kHalo);

  const auto expectWindow = [&](const TexelWindow& tile, uint64_t newTexels) {
    const uint64_t before = source.texelsRead();
    const HeightWindow& window = reader.windowFor(tile);
    const TexelWindow want = tileReadWindow(geometry, kHalo, tile);
    EXPECT_EQ(source.texelsRead() - before, newTexels) << "tile at " << tile.col;
    EXPECT_EQ(window.texels.col, want.col);
    EXPECT_EQ(window.texels.row, want.row);
    EXPECT_EQ(window.texels.width, want.width);
    EXPECT_EQ(window.texels.height, want.height);
    EXPECT_EQ(window.z.size(), want.texelCount());
    size_t differing = 0;
    for (int row = want.row; row < want.row + want.height; ++row) {
      for (int col = want.col; col < want.col + want.width; ++col) {
        differing += window.at(col, row) != field.at(col, row);
      }
    }
    EXPECT_EQ(differing, 0u) << "tile at " << tile.col << "," << tile.row;
  };
  // Tile row 1 (rows 32..63): the window's rows 2..89, 88 of them.
  const uint64_t rows = 88;
  expectWindow({0, 32, kTile, kTile}, rows * (kTile + kHalo));    // columns 0..61
  expectWindow({32, 32, kTile, kTile}, rows * kTile);             // 2..93: 62..93 new
  expectWindow({64, 32, kTile, kTile}, rows * kTile);             // 34..125
  expectWindow({64, 32, kTile, kTile}, 0);                        // the same: nothing
  expectWindow({128, 32, kTile, kTile}, rows * (kTile + kTile));  // 98..189: 126..189
  expectWindow({192, 32, 8, kTile}, rows * (200 - 190));          // 162..199
  expectWindow({128, 32, kTile, kTile}, rows * (162 - 98));       // back: 98..161 new
  // Another tile row: the whole window again (rows 34..89, columns 66..157).
  expectWindow({96, 64, kTile, 26}, uint64_t{56} * 92);
  EXPECT_EQ(reader.texelsRead(), source.texelsRead());
}

// bakeTiledInBands reads each tile row's windows, slid along it: each
// texel of a tile row's window rows once, not a window per tile; and the
// folder equals the in-memory tiled bake's.
TEST(TileWindow, BakesInWindowsReadEachTileRowOnceAndEqualTheInMemoryBake) {
  test::TempDir dir;
  const Heightfield field = fbmField(230, 100);
  const fs::path path = dir.path() / "dem.tif";
  writeFloatGeoTiff(path.string(), field.width, field.height, field.z.data(),
                    test::testGeoReference(false));
  const DemSource source(path.string(), DemLoadOptions{});
  const Heightfield geometry = demGeometry(source, DemLoadOptions{});
  const Heightfield loaded = loadDem(path.string());
  BakeOptions bake = options(0.0, false, false);
  bake.azimuths = 8;
  TiledBakeOptions tiled;
  tiled.tileSize = 32;
  tiled.farField.nearReachM = 300.0;
  const fs::path memory = dir.path() / "memory", windows = dir.path() / "windows";
  bakeTiled(loaded, bake, tiled, memory.string());
  const uint64_t pass = source.texelsRead();
  const TiledBakeSummary summary =
      bakeTiledInBands(source, geometry, bake, tiled, windows.string());
  EXPECT_EQ(summary.baked, 32);
  const int halo = tileHalo(geometry, bake, tiled);
  ASSERT_LT(32 + 2 * halo, field.width) << "the windows hold every column: the test tests nothing";
  uint64_t want = 0;  // per tile row, its window's rows of every column
  for (int row = 0; row < field.height; row += 32) {
    const TexelWindow read = tileReadWindow(geometry, halo, {0, row, 32, std::min(32, 100 - row)});
    want += static_cast<uint64_t>(read.height) * field.width;
  }
  EXPECT_EQ(summary.texelsRead, want);
  EXPECT_EQ(source.texelsRead() - pass, want + field.texelCount());  // and the checksum pass
  const ApertureMap a = readApertureMap(memory.string()), b = readApertureMap(windows.string());
  EXPECT_EQ(a.texels, b.texels);
}

}  // namespace
}  // namespace aal
