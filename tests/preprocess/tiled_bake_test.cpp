// The tiled bake: tiles equal the in-memory bake bit for bit (seams
// included), the tile folder reads as one map, interrupted bakes resume.
#include "aperture/preprocess/tiled_bake.h"

#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <string>
#include <vector>

#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/sky_view_factor_tiles.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

// 300 x 200 fBm at 30 m cells, 600 m of relief: tiles of 64 leave partial
// tiles at the right (44) and bottom (8) edges.
Heightfield fbmField(int width = 300, int height = 200) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 30;
  s.seed = 11;
  s.featureSizeTexels = 40;
  s.octaves = 5;
  return makeSyntheticTerrain(s);
}

// The same terrain on a geographic grid far north, where the x spacing
// shrinks by ~11 % from the southern to the northern edge.
Heightfield geographicField() {
  Heightfield field = fbmField(150, 120);
  field.rowCellSizeXM.resize(static_cast<size_t>(field.height));
  for (int row = 0; row < field.height; ++row) {
    const double latDeg = 62.0 - row * 0.03;
    field.rowCellSizeXM[static_cast<size_t>(row)] =
        60.0 * std::cos(latDeg * std::numbers::pi / 180.0);
  }
  field.cellSizeXM = field.rowCellSizeXM[static_cast<size_t>(field.height / 2)];
  return field;
}

// Expects `read` to throw InputError whose message names `name` (a tile).
template <class Read>
void expectInputErrorNaming(Read&& read, const std::string& name, const char* otherwise) {
  try {
    read();
    ADD_FAILURE() << otherwise;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
  }
}

BakeOptions distanceLimited(double maxDistanceM, bool clampEdge = false) {
  BakeOptions o;
  o.azimuths = 24;  // not a multiple of 8: lines at every kind of slope
  o.maxDistanceM = maxDistanceM;
  o.clampEdge = clampEdge;
  return o;
}

// Counts texels of `tile` (at `window` in the field) that differ in any bit
// from the whole-field bake `whole`.
size_t differingTexels(const ApertureMap& whole, const ApertureMap& tile,
                       const TexelWindow& window) {
  size_t differing = 0;
  for (int row = 0; row < window.height; ++row) {
    for (int col = 0; col < window.width; ++col) {
      const float* a = &whole.texels[4 * (static_cast<size_t>(row + window.row) * whole.width +
                                          static_cast<size_t>(col + window.col))];
      const float* b = &tile.texels[4 * (static_cast<size_t>(row) * tile.width + col)];
      if (std::memcmp(a, b, 4 * sizeof(float)) != 0) ++differing;
    }
  }
  return differing;
}

// Bakes every tile of `field` with bakeApertureWindow and expects each to
// equal the whole bake bit for bit.
void expectTilesEqualWholeBake(const Heightfield& field, const BakeOptions& o, int tileSize) {
  const BakeResult whole = bakeApertures(field, o);
  for (int row = 0; row < field.height; row += tileSize) {
    for (int col = 0; col < field.width; col += tileSize) {
      const TexelWindow window{col, row, std::min(tileSize, field.width - col),
                               std::min(tileSize, field.height - row)};
      const BakeResult tile = bakeApertureWindow(field, window, o);
      ASSERT_EQ(tile.aperture.width, window.width);
      ASSERT_EQ(tile.aperture.height, window.height);
      EXPECT_EQ(differingTexels(whole.aperture, tile.aperture, window), 0u)
          << "tile at " << col << "," << row;
    }
  }
}

TEST(TiledBake, TilesEqualTheInMemoryBakeWithOpenEdges) {
  expectTilesEqualWholeBake(fbmField(), distanceLimited(150), 64);
}

TEST(TiledBake, TilesEqualTheInMemoryBakeWithClampedEdgesAndCurvature) {
  BakeOptions o = distanceLimited(200, /*clampEdge=*/true);
  o.curvature = true;
  expectTilesEqualWholeBake(fbmField(), o, 64);
}

TEST(TiledBake, TilesEqualTheInMemoryBakeOnAGeographicGrid) {
  expectTilesEqualWholeBake(geographicField(), distanceLimited(300, true), 32);
}

// A distance reaching across several tiles: the lines of a tile start
// three tiles away.
TEST(TiledBake, DistanceLongerThanATile) {
  expectTilesEqualWholeBake(fbmField(120, 90), distanceLimited(1500), 16);
}

// A limit too long for the block sweep to scan goes to the line sweep
// (sweepHorizonRuns): its windows too equal the whole bake, with clamped
// edges and curvature. The field is longer than the limit (18 against
// 16 km), so that a tile's lines start inside it.
TEST(TiledBake, TilesEqualTheInMemoryBakeWithALimitTooLongToScan) {
  const Heightfield field = fbmField(600, 40);
  BakeOptions o = distanceLimited(16000, /*clampEdge=*/true);
  o.curvature = true;
  ASSERT_FALSE(detail::scansWithinLimit(prepareBakeTerrain(field), {true, 0.0, o.maxDistanceM}));
  expectTilesEqualWholeBake(field, o, 100);
}

// The sweep over a window equals the whole sweep there, also without a
// distance limit (its lines then start at the field's edge).
TEST(TiledBake, WindowSweepEqualsTheWholeSweep) {
  const Heightfield field = fbmField(90, 60);
  const BakeTerrain whole = prepareBakeTerrain(field);
  const TexelWindow window{23, 17, 40, 25};
  const BakeTerrain part = prepareBakeTerrain(field, window);
  for (const double maxDistanceM : {0.0, 200.0}) {
    HorizonSweepOptions o;
    o.maxDistanceM = maxDistanceM;
    o.clampEdge = true;
    for (int a = 0; a < 24; ++a) {
      const double phi = a * 2 * std::numbers::pi / 24;
      std::vector<double> all(field.texelCount(), NAN), some(window.texelCount(), NAN);
      sweepHorizons(whole, phi, o, [&](size_t i, double t) { all[i] = t; });
      sweepHorizons(part, phi, o, [&](size_t i, double t) { some[i] = t; });
      size_t differing = 0;
      for (int row = 0; row < window.height; ++row) {
        for (int col = 0; col < window.width; ++col) {
          const double a1 = all[field.index(col + window.col, row + window.row)];
          const double a2 = some[part.windowIndex(col + window.col, row + window.row)];
          if (std::memcmp(&a1, &a2, sizeof a1) != 0) ++differing;
        }
      }
      EXPECT_EQ(differing, 0u) << "azimuth " << a << ", max distance " << maxDistanceM;
    }
  }
}

// The texels either side of every tile boundary, on a map baked in the
// folder and read back, equal those of the single-file bake.
TEST(TiledBake, SeamsMatchTheSingleFileBake) {
  test::TempDir dir;
  const Heightfield field = fbmField();
  const BakeOptions o = distanceLimited(150);
  BakeResult whole = bakeApertures(field, o);
  whole.aperture.info.source = "fbm.tif";
  const std::string single = (dir.path() / "whole.exr").string();
  writeApertureMap(single, whole.aperture, true);
  TiledBakeOptions t;
  t.tileSize = 64;
  t.sourceName = "fbm.tif";
  const std::string folder = (dir.path() / "tiles").string();
  const TiledBakeSummary summary = bakeTiled(field, o, t, folder);
  EXPECT_EQ(summary.tiles, 5 * 4);
  EXPECT_EQ(summary.baked, 20);
  const ApertureMap a = readApertureMap(single), b = readApertureMap(folder);
  ASSERT_EQ(b.width, field.width);
  ASSERT_EQ(b.height, field.height);
  for (int boundary = 64; boundary < field.width; boundary += 64) {
    for (int row = 0; row < field.height; ++row) {
      for (int col : {boundary - 1, boundary}) {
        const size_t i = 4 * field.index(col, row);
        EXPECT_EQ(std::memcmp(&a.texels[i], &b.texels[i], 16), 0) << col << "," << row;
      }
    }
  }
  for (int boundary = 64; boundary < field.height; boundary += 64) {
    for (int col = 0; col < field.width; ++col) {
      for (int row : {boundary - 1, boundary}) {
        const size_t i = 4 * field.index(col, row);
        EXPECT_EQ(std::memcmp(&a.texels[i], &b.texels[i], 16), 0) << col << "," << row;
      }
    }
  }
  EXPECT_EQ(a.texels, b.texels);  // and everything else
  EXPECT_EQ(b.info.sourceChecksum, heightfieldChecksum(field));
  EXPECT_EQ(b.info.source, "fbm.tif");
  EXPECT_EQ(b.info.maxDistanceM, 150);
  EXPECT_NO_THROW(checkApertureMatchesDem(b, folder, field, "fbm.tif"));
}

// The streaming reader puts rows together from the tiles, for row bands
// that start and end inside tiles.
TEST(TiledBake, ReaderAssemblesRowsFromTiles) {
  test::TempDir dir;
  const Heightfield field = fbmField(100, 70);
  const BakeOptions o = distanceLimited(100);
  BakeResult whole = bakeApertures(field, o);
  const std::string single = (dir.path() / "whole.exr").string();
  writeApertureMap(single, whole.aperture, true);
  TiledBakeOptions t;
  t.tileSize = 16;
  const std::string folder = (dir.path() / "tiles").string();
  bakeTiled(field, o, t, folder);
  ApertureMapReader a(single), b(folder);
  EXPECT_EQ(b.header().width, 100);
  EXPECT_EQ(b.header().height, 70);
  EXPECT_EQ(b.header().info.sourceChecksum, a.header().info.sourceChecksum);
  for (auto [first, end] : {std::pair{0, 70}, {5, 37}, {16, 32}, {60, 70}, {3, 4}, {40, 40}}) {
    const size_t count = static_cast<size_t>(end - first) * 100 * 4;
    std::vector<uint16_t> fromFile(count), fromTiles(count);
    a.readHalfRows(first, end, fromFile.data());
    b.readHalfRows(first, end, fromTiles.data());
    EXPECT_EQ(fromFile, fromTiles) << "rows " << first << " to " << end;
  }
}

TEST(TiledBake, InterruptedBakeResumesFromItsFinishedTiles) {
  test::TempDir dir;
  const Heightfield field = fbmField(200, 150);
  BakeOptions o = distanceLimited(120, true);
  TiledBakeOptions t;
  t.tileSize = 64;  // 4 x 3 tiles
  const std::string reference = (dir.path() / "reference").string();
  bakeTiled(field, o, t, reference);

  // Stop past half way: during the fifth tile (tiles of 64, 64, 64 and 8
  // texels across; 64, 64 and 22 down).
  const std::string folder = (dir.path() / "tiles").string();
  std::atomic<bool> cancel{false};
  o.cancel = &cancel;
  o.progress = [&](double fraction) {
    if (fraction > 0.5) cancel = true;
  };
  EXPECT_THROW(bakeTiled(field, o, t, folder), BakeCancelled);
  EXPECT_FALSE(fs::exists(fs::path(folder) / "index.txt"));
  std::vector<fs::file_time_type> written;
  int finished = 0;
  for (int i = 0; i < 12; ++i) {
    const fs::path tile = fs::path(folder) / apertureTileName(i / 4, i % 4);
    if (fs::exists(tile)) {
      ++finished;
      written.push_back(fs::last_write_time(tile));
    }
  }
  EXPECT_EQ(finished, 4);
  // Unfinished, the folder is no map yet.
  EXPECT_THROW(readApertureMap(folder), InputError);
  EXPECT_THROW(ApertureMapReader{folder}, InputError);

  cancel = false;
  o.progress = nullptr;
  const TiledBakeSummary summary = bakeTiled(field, o, t, folder);
  EXPECT_EQ(summary.tiles, 12);
  EXPECT_EQ(summary.resumed, finished);
  EXPECT_EQ(summary.baked, 12 - finished);
  for (int i = 0; i < finished; ++i) {
    const fs::path tile = fs::path(folder) / apertureTileName(i / 4, i % 4);
    EXPECT_EQ(fs::last_write_time(tile), written[static_cast<size_t>(i)]) << tile;
  }
  EXPECT_EQ(readApertureMap(folder).texels, readApertureMap(reference).texels);

  // Run again on the finished folder: nothing to bake.
  EXPECT_EQ(bakeTiled(field, o, t, folder).resumed, 12);
}

TEST(TiledBake, AFolderOfAnotherBakeIsAnError) {
  test::TempDir dir;
  const Heightfield field = fbmField(100, 70);
  TiledBakeOptions t;
  t.tileSize = 32;
  const std::string folder = (dir.path() / "tiles").string();
  bakeTiled(field, distanceLimited(100), t, folder);
  // Other options, another DEM, another tile size: nothing is overwritten.
  EXPECT_THROW(bakeTiled(field, distanceLimited(110), t, folder), InputError);
  EXPECT_THROW(bakeTiled(fbmField(100, 71), distanceLimited(100), t, folder), InputError);
  TiledBakeOptions other = t;
  other.tileSize = 48;
  EXPECT_THROW(bakeTiled(field, distanceLimited(100), other, folder), InputError);
  // Without the index and the manifest (a bake interrupted before manifests
  // existed), a tile of another bake is found as such.
  fs::remove(fs::path(folder) / "index.txt");
  fs::remove(fs::path(folder) / kTiledBakeManifestName);
  expectInputErrorNaming([&] { bakeTiled(field, distanceLimited(110), t, folder); },
                         "tile_0000_0000.exr", "a tile of another bake was accepted");
}

// A folder an older bake left unfinished records the version 1 (byte-serial)
// checksum in its manifest and tiles: the same bake of the same DEM resumes
// it with that checksum (the folder stays one bake); another DEM is
// refused. A new folder records the row-hash checksum.
TEST(TiledBake, AFolderWithTheOlderChecksumResumesAsOneBake) {
  test::TempDir dir;
  const Heightfield field = fbmField(100, 70);
  const BakeOptions o = distanceLimited(100);
  TiledBakeOptions t;
  t.tileSize = 32;  // 4 x 3 tiles
  const std::string folder = (dir.path() / "tiles").string();
  bakeTiled(field, o, t, folder);
  const std::string legacy = legacyHeightfieldChecksum(field);
  ApertureTileIndex index = readApertureTileIndex(folder);
  EXPECT_EQ(index.map.info.sourceChecksum, heightfieldChecksum(field));
  // The folder as the older bake would have left it, a tile short.
  index.map.info.sourceChecksum = legacy;
  writeApertureTileIndex(folder, index, kTiledBakeManifestName);
  for (int i = 0; i < 12; ++i) {
    const std::string tile = (fs::path(folder) / apertureTileName(i / 4, i % 4)).string();
    ApertureMap map = readApertureMap(tile);
    map.info.sourceChecksum = legacy;
    writeApertureMap(tile, map, t.halfFloat, t.compression);
  }
  fs::remove(fs::path(folder) / "index.txt");
  fs::remove(fs::path(folder) / apertureTileName(1, 2));

  Heightfield other = field;  // one height differs
  other.z[4321] += 0.5f;
  EXPECT_THROW(bakeTiled(other, o, t, folder), InputError);
  const TiledBakeSummary resumed = bakeTiled(field, o, t, folder);
  EXPECT_EQ(resumed.baked, 1);
  EXPECT_EQ(resumed.resumed, 11);
  EXPECT_EQ(readApertureTileIndex(folder).map.info.sourceChecksum, legacy);
  ApertureMapReader reader(folder);
  EXPECT_EQ(reader.header().info.sourceChecksum, legacy);
  reader.verify();  // every tile, the new one too, belongs to the index
  EXPECT_NO_THROW(checkApertureMatchesDem(reader.header(), folder, field, "fbm.tif"));
  EXPECT_THROW(checkApertureMatchesDem(reader.header(), folder, other, "b.tif"), InputError);
}

TEST(TiledBake, CorruptOrMissingTilesAreNamed) {
  test::TempDir dir;
  const Heightfield field = fbmField(100, 70);
  TiledBakeOptions t;
  t.tileSize = 32;
  const std::string folder = (dir.path() / "tiles").string();
  bakeTiled(field, distanceLimited(100), t, folder);
  const ApertureMap good = readApertureMap(folder);

  const fs::path tile = fs::path(folder) / apertureTileName(1, 2);
  fs::resize_file(tile, fs::file_size(tile) / 2);
  expectInputErrorNaming([&] { readApertureMap(folder); }, "tile_0001_0002.exr",
                         "a truncated tile was read");
  expectInputErrorNaming(
      [&] {
        ApertureMapReader reader(folder);
        std::vector<uint16_t> rows(100 * 70 * 4);
        reader.readHalfRows(0, 70, rows.data());
      },
      "tile_0001_0002.exr", "a truncated tile was streamed");
  // Resuming bakes the broken tile again.
  const TiledBakeSummary summary = bakeTiled(field, distanceLimited(100), t, folder);
  EXPECT_EQ(summary.baked, 1);
  EXPECT_EQ(readApertureMap(folder).texels, good.texels);

  fs::remove(tile);
  expectInputErrorNaming([&] { readApertureMap(folder); }, "tile_0001_0002.exr",
                         "a missing tile was not noticed");
}

TEST(TiledBake, AFolderOfAnotherDemDoesNotMatch) {
  test::TempDir dir;
  const Heightfield field = fbmField(100, 70);
  TiledBakeOptions t;
  t.tileSize = 32;
  const std::string folder = (dir.path() / "tiles").string();
  bakeTiled(field, distanceLimited(100), t, folder);
  const ApertureMapReader reader(folder);
  EXPECT_NO_THROW(checkApertureMatchesDem(reader.header(), folder, field, "a.tif"));
  Heightfield other = field;
  other.z[17] += 1.0f;
  EXPECT_THROW(checkApertureMatchesDem(reader.header(), folder, other, "b.tif"), InputError);
  EXPECT_THROW(checkApertureMatchesDem(reader.header(), folder, fbmField(100, 71), "c.tif"),
               InputError);
}

TEST(TiledBake, RejectsWhatItCannotBake) {
  const Heightfield field = fbmField(40, 30);
  TiledBakeOptions t;
  BakeOptions o = distanceLimited(100);
  t.tileSize = kMinTileSize - 1;
  EXPECT_THROW(checkTiledBakeOptions(o, t), std::invalid_argument);
  t.tileSize = kMaxTileSize + 1;
  EXPECT_THROW(checkTiledBakeOptions(o, t), std::invalid_argument);
  t.tileSize = 16;
  EXPECT_NO_THROW(checkTiledBakeOptions(o, t));
  o.maxDistanceM = 0;  // the far field completes the horizons
  EXPECT_NO_THROW(checkTiledBakeOptions(o, t));
  t.farField.resolution = 0;
  EXPECT_THROW(checkTiledBakeOptions(o, t), std::invalid_argument);
  t.farField = {};
  // A partial window without a distance limit or a far field would need
  // the whole DEM.
  EXPECT_THROW(bakeApertureWindow(field, TexelWindow{0, 0, 16, 16}, o), std::invalid_argument);
  EXPECT_NO_THROW(bakeApertureWindow(field, TexelWindow{0, 0, 40, 30}, o));
  o = distanceLimited(100);
  o.method = BakeMethod::Rays;
  EXPECT_THROW(checkTiledBakeOptions(o, t), std::invalid_argument);
  // The SVF is written beside the tiles, placed by the DEM's
  // georeferencing, which a synthetic field has not.
  o = distanceLimited(100);
  o.skyViewFactor = true;
  EXPECT_NO_THROW(checkTiledBakeOptions(o, t));
  ASSERT_EQ(field.geo.crs, CrsKind::None);
  const test::TempDir dir;
  EXPECT_THROW(bakeTiled(field, o, t, (dir.path() / "t").string()), InputError);
  EXPECT_FALSE(fs::exists(dir.path() / "t"));  // refused before the folder is made
  EXPECT_NO_THROW(checkSkyViewFactorTiles(field, false));
  EXPECT_THROW(bakeApertureWindow(field, TexelWindow{30, 0, 16, 16}, distanceLimited(100)),
               std::invalid_argument);  // outside the field
}

// A folder as a bake of `field` interrupted past half way leaves it: tiles
// of 32 (4 x 3), the manifest, no index, and a temporary of a killed run
// that a bake's sweep would remove.
void interruptedBake(const Heightfield& field, const std::string& folder) {
  BakeOptions o = distanceLimited(100);
  std::atomic<bool> cancel{false};
  o.cancel = &cancel;
  o.progress = [&](double fraction) {
    if (fraction > 0.5) cancel = true;
  };
  TiledBakeOptions t;
  t.tileSize = 32;
  t.sourceName = "first.tif";
  EXPECT_THROW(bakeTiled(field, o, t, folder), BakeCancelled);
  ASSERT_TRUE(fs::exists(fs::path(folder) / apertureTileName(0, 0)));
  ASSERT_TRUE(fs::exists(fs::path(folder) / kTiledBakeManifestName));
  ASSERT_FALSE(fs::exists(fs::path(folder) / "index.txt"));
  std::ofstream(fs::path(folder) /
                (".tile_0002_0000.tmp-" + std::to_string(test::deadPid()) + "-0.exr"))
      << "killed";
}

// A second bake into a folder that a running bake holds
// (its flock) is refused before it touches anything: before the sweep that
// deleted the first bake's temporary tile.
TEST(TiledBake, ASecondBakeIntoALockedFolderIsRefusedTouchingNothing) {
  test::TempDir dir;
  const Heightfield field = fbmField(100, 70);
  const std::string folder = (dir.path() / "tiles").string();
  interruptedBake(field, folder);
  // The interrupted bake took its lock file with it.
  const auto interrupted = test::folderContents(folder);
  EXPECT_EQ(interrupted.count(kTiledBakeLockName), 0u);
  {
    // As a running bake holds it: the same file, another open of it.
    const TiledBakeLock running(folder);
    const auto before = test::folderContents(folder);
    TiledBakeOptions t;
    t.tileSize = 32;
    t.sourceName = "first.tif";
    try {
      bakeTiled(field, distanceLimited(100), t, folder);
      ADD_FAILURE() << "baked into a locked folder";
    } catch (const TiledBakeBusy& e) {
      EXPECT_NE(std::string(e.what()).find(folder), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("another aal-bake"), std::string::npos) << e.what();
    }
    EXPECT_EQ(test::changedFiles(before, test::folderContents(folder)), std::vector<std::string>{});
    EXPECT_THROW(TiledBakeLock{folder}, TiledBakeBusy);
  }
  // Released by the bake that held it, the lock file goes too.
  EXPECT_EQ(test::changedFiles(interrupted, test::folderContents(folder)),
            std::vector<std::string>{});
  {
    // A lock held with flock by hand (another program) counts too.
    const int fd =
        ::open((fs::path(folder) / kTiledBakeLockName).c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    const auto before = test::folderContents(folder);
    TiledBakeOptions t;
    t.tileSize = 32;
    t.sourceName = "first.tif";
    EXPECT_THROW(bakeTiled(field, distanceLimited(100), t, folder), TiledBakeBusy);
    EXPECT_EQ(test::changedFiles(before, test::folderContents(folder)), std::vector<std::string>{});
    ::close(fd);
  }
  // Released, the same bake resumes (and sweeps the killed run's temporary).
  TiledBakeOptions t;
  t.tileSize = 32;
  t.sourceName = "first.tif";
  const TiledBakeSummary summary = bakeTiled(field, distanceLimited(100), t, folder);
  EXPECT_GT(summary.resumed, 0);
  EXPECT_EQ(summary.resumed + summary.baked, 12);
  for (const auto& [name, bytes] : test::folderContents(folder)) {
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
  }
  // The lock file the other program left is removed by the bake that took it over.
  EXPECT_FALSE(fs::exists(fs::path(folder) / kTiledBakeLockName));
}

// A bake of another DEM into a folder holding a bake (interrupted or
// finished) is refused, saying whose bake it holds; nothing is touched.
TEST(TiledBake, ABakeOfAnotherDemIntoTheFolderIsRefusedTouchingNothing) {
  test::TempDir dir;
  const Heightfield first = fbmField(100, 70);
  Heightfield second = first;
  second.z[123] += 5.0f;  // the same size: only the checksum tells them apart
  const std::string folder = (dir.path() / "tiles").string();
  interruptedBake(first, folder);
  TiledBakeOptions t;
  t.tileSize = 32;
  t.sourceName = "second.tif";
  auto expectRefused = [&](const Heightfield& field, const BakeOptions& o,
                           const TiledBakeOptions& tiling, const std::string& says) {
    const auto before = test::folderContents(folder);
    try {
      bakeTiled(field, o, tiling, folder);
      ADD_FAILURE() << "baked into another bake's folder";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(says), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("first.tif"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("another folder"), std::string::npos) << e.what();
    }
    EXPECT_EQ(test::changedFiles(before, test::folderContents(folder)), std::vector<std::string>{});
  };
  expectRefused(second, distanceLimited(100), t, "another DEM");
  expectRefused(fbmField(90, 70), distanceLimited(100), t, "another DEM");
  // The same DEM with other options or tiles is another bake too.
  TiledBakeOptions sameDem = t;
  sameDem.sourceName = "first.tif";
  expectRefused(first, distanceLimited(110), sameDem, "other options");
  sameDem.tileSize = 48;
  expectRefused(first, distanceLimited(100), sameDem, "tiles of 32");
  sameDem.tileSize = 32;
  // Without a manifest (a bake interrupted before manifests existed), its
  // tiles tell.
  fs::rename(fs::path(folder) / kTiledBakeManifestName, dir.path() / "manifest.txt");
  expectRefused(second, distanceLimited(100), t, "the DEM it was baked from differ");
  expectRefused(first, distanceLimited(110), sameDem, "the bake options differ");
  fs::rename(dir.path() / "manifest.txt", fs::path(folder) / kTiledBakeManifestName);

  // Finished, the same.
  bakeTiled(first, distanceLimited(100), sameDem, folder);
  ASSERT_TRUE(fs::exists(fs::path(folder) / "index.txt"));
  expectRefused(second, distanceLimited(100), t, "another DEM");
}

}  // namespace
}  // namespace aal
