// Command-line contract of aal-bake's tiled bake, and aal-render and aal-view
// reading the tile folder as the aperture map.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

fs::path writeDem(const TempDir& dir, int width, int height, uint64_t seed = 1) {
  return test::writeSyntheticDem(dir, width, height, seed);
}

const std::string kOptions = " --azimuths 16 --max-distance 200 -q";

// Bakes `dem` into the single file a.exr and the tile folder a.tiles (tiles
// of 32) in `dir`; {file, folder}, empty paths when a bake failed.
std::pair<fs::path, fs::path> bakeSingleAndTiled(const TempDir& dir, const fs::path& dem) {
  const fs::path single = dir.path() / "a.exr", folder = dir.path() / "a.tiles";
  if (runTool("aal-bake", quoted(dem) + " -o " + quoted(single) + kOptions).exitCode != 0 ||
      runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) + " --tile-size 32" + kOptions)
              .exitCode != 0) {
    return {};
  }
  return {single, folder};
}

TEST(AalBakeTiled, FolderEqualsTheSingleFileBake) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 90, 70);
  const fs::path single = dir.path() / "a.exr", folder = dir.path() / "a.tiles";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(single) + kOptions).exitCode, 0);
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) +
                                         " --tile-size 32 --azimuths 16 --max-distance 200");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("32-texel tiles (9 baked, 0 resumed)"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(folder / "index.txt"));
  const ApertureMap a = readApertureMap(single.string()), b = readApertureMap(folder.string());
  EXPECT_EQ(b.width, 90);
  EXPECT_EQ(b.height, 70);
  EXPECT_EQ(a.texels, b.texels);
  EXPECT_EQ(a.info.sourceChecksum, b.info.sourceChecksum);
  EXPECT_EQ(b.info.source, dem.filename().string());
}

// A DEM read in windows (--low-memory): each tile's window holds only its
// texels and those within the max distance, yet every tile equals
// the single-file bake, on a projected and on a geographic grid (whose x
// spacing changes with the row).
TEST(AalBakeTiled, WindowsOfTheDemEqualTheSingleFileBake) {
  TempDir dir;
  for (const bool geographic : {false, true}) {
    SyntheticTerrainOptions s;
    s.width = 70;
    s.height = 160;
    s.cellSizeM = 30;
    s.seed = 4;
    s.featureSizeTexels = 16;
    const Heightfield field = makeSyntheticTerrain(s);
    const GeoReference geo = test::testGeoReference(geographic);
    const fs::path dem = dir.path() / (geographic ? "geo.tif" : "utm.tif");
    writeFloatGeoTiff(dem.string(), s.width, s.height, field.z.data(), geo);
    const std::string options = " --azimuths 32 --max-distance 250 -q";
    const fs::path single = dir.path() / "single.exr", folder = dir.path() / "bands";
    fs::remove_all(folder);
    ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(single) + options).exitCode, 0);
    const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) +
                                           " --tile-size 32 --low-memory --azimuths 32 "
                                           "--max-distance 250");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_NE(r.out.find("32-texel tiles read in windows (15 baked"), std::string::npos) << r.out;
    const ApertureMap a = readApertureMap(single.string()), b = readApertureMap(folder.string());
    EXPECT_EQ(a.texels, b.texels) << (geographic ? "geographic" : "projected");
    EXPECT_EQ(a.info.sourceChecksum, b.info.sourceChecksum);
  }
}

// A DEM several tiles wide and tall read in windows (--low-memory): each
// tile's window holds the tile and its halo (with the max distance a part
// of the rows and of the columns; the far field's shortest reach, 128
// cells, 5952 m of the geographic grid's smallest cell, covers this DEM:
// tests/preprocess/tile_window_test.cpp holds partial windows under the
// far field), yet the folder is the in-memory
// tiled bake's byte for byte (the SVF GeoTIFFs and the VRT too), with a
// max distance and with the far field, on a projected and on a geographic
// grid; 200 x 130 in tiles of 32 leaves tiles of 8 columns and of 2 rows at
// the edges.
TEST(AalBakeTiled, WindowsOfAWideDemEqualTheInMemoryFolder) {
  TempDir dir;
  const std::string fixedDate = "SOURCE_DATE_EPOCH=1700000000";
  for (const bool geographic : {false, true}) {
    SyntheticTerrainOptions s;
    s.width = 200;
    s.height = 130;
    s.cellSizeM = 30;
    s.seed = 7;
    s.featureSizeTexels = 20;
    const Heightfield field = makeSyntheticTerrain(s);
    const fs::path dem = dir.path() / (geographic ? "geo.tif" : "utm.tif");
    writeFloatGeoTiff(dem.string(), s.width, s.height, field.z.data(),
                      test::testGeoReference(geographic));
    for (const std::string options :
         {" --tile-size 32 --azimuths 12 --max-distance 200 --svf",
          " --tile-size 32 --azimuths 12 --near-reach 6000 --edge clamp --curvature --svf"}) {
      SCOPED_TRACE(std::string(geographic ? "geographic" : "projected") + options);
      const fs::path memory = dir.path() / "memory", windows = dir.path() / "windows";
      fs::remove_all(memory);
      fs::remove_all(windows);
      auto r =
          runTool("aal-bake", quoted(dem) + " -o " + quoted(memory) + options + " -q", fixedDate);
      ASSERT_EQ(r.exitCode, 0) << r.out;
      r = runTool("aal-bake", quoted(dem) + " -o " + quoted(windows) + options + " --low-memory",
                  fixedDate);
      ASSERT_EQ(r.exitCode, 0) << r.out;
      EXPECT_NE(r.out.find("32-texel tiles read in windows (35 baked, 0 resumed), windows of"),
                std::string::npos)
          << r.out;
      const test::FolderContents want = test::folderContents(memory),
                                 have = test::folderContents(windows);
      EXPECT_EQ(have.size(), 35u + 35u + 3u);  // EXRs, GeoTIFFs, VRT, index, manifest
      for (const auto& [name, bytes] : want) {
        ASSERT_TRUE(have.count(name)) << name;
        EXPECT_TRUE(have.at(name) == bytes) << name << " differs";
      }
    }
  }
}

TEST(AalBakeTiled, BandsRefuseVoidsAndNeedTiles) {
  TempDir dir;
  std::vector<float> z(40 * 40, 100.0f);
  z[40 * 20 + 7] = std::numeric_limits<float>::quiet_NaN();
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.stepX = geo.stepY = 30;
  const fs::path dem = dir.path() / "holes.tif", folder = dir.path() / "t";
  writeFloatGeoTiff(dem.string(), 40, 40, z.data(), geo);
  auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) +
                                   " --tile-size 16 --low-memory --max-distance 100 -q");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("gdal_fillnodata.py"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(folder / apertureTileName(0, 0)));
  r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") +
                              " --low-memory --max-distance 100 -q");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("--tile-size"), std::string::npos) << r.out;
}

TEST(AalBakeTiled, RunningAgainResumesFromTheFinishedTiles) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 90, 70);
  const fs::path folder = dir.path() / "a.tiles";
  const std::string command =
      quoted(dem) + " -o " + quoted(folder) + " --tile-size 32 --azimuths 16 --max-distance 200";
  ASSERT_EQ(runTool("aal-bake", command).exitCode, 0);
  const ApertureMap whole = readApertureMap(folder.string());
  // As an interrupted run leaves it: some tiles, no index.
  fs::remove(folder / "index.txt");
  fs::remove(folder / apertureTileName(1, 1));
  fs::remove(folder / apertureTileName(2, 0));
  const auto r = runTool("aal-bake", command);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("(2 baked, 7 resumed)"), std::string::npos) << r.out;
  EXPECT_EQ(readApertureMap(folder.string()).texels, whole.texels);
  // Every tile finished: all resumed, and no rate is claimed for no work.
  const auto again = runTool("aal-bake", command);
  ASSERT_EQ(again.exitCode, 0) << again.out;
  EXPECT_NE(again.out.find("(0 baked, 9 resumed)"), std::string::npos) << again.out;
  EXPECT_NE(again.out.find("(nothing baked)"), std::string::npos) << again.out;
  // Other options on the same folder: refused, nothing overwritten.
  const auto other = runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) +
                                             " --tile-size 32 --azimuths 32 --max-distance 200");
  EXPECT_EQ(other.exitCode, 2) << other.out;
  EXPECT_NE(other.out.find("another folder"), std::string::npos) << other.out;
  EXPECT_EQ(readApertureMap(folder.string()).texels, whole.texels);
}

TEST(AalBakeTiled, BadTiledBakesExitWithTwoBeforeWork) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 40, 40);
  const fs::path folder = dir.path() / "t";
  const std::string out = quoted(dem) + " -o " + quoted(folder);
  const fs::path file = dir.path() / "file.exr";
  std::ofstream(file) << "a file";
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {
           Case{out + " --tile-size 8 --max-distance 100", "--tile-size"},
           Case{out + " --tile-size 20000 --max-distance 100", "--tile-size"},
           Case{out + " --tile-size 16 --max-distance 100 --method rays", "sweep"},
           Case{out + " --tile-size 16 --max-distance 100 --near-reach 600", "--near-reach"},
           Case{quoted(dem) + " -o " + quoted(file) + " --near-reach 600", "--near-reach"},
           Case{out + " --tile-size 16 --max-distance 100 --svf " + quoted(dir.path() / "s.tif"),
                "give --svf without a path"},
           Case{quoted(dem) + " -o " + quoted(file) + " --tile-size 16 --max-distance 100",
                "is a file"},
           Case{quoted(dem) + " -o " + quoted(dir.path() / "no" / "t") +
                    " --tile-size 16 --max-distance 100",
                "does not exist"},
       }) {
    const auto r = runTool("aal-bake", c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(r.out.find("texel-azimuths"), std::string::npos) << "baked anyway: " << r.out;
  }
  EXPECT_FALSE(fs::exists(folder));
}

TEST(AalBakeTiled, HelpStatesTheLimit) {
  const auto r = runTool("aal-bake", "--help");
  ASSERT_EQ(r.exitCode, 0);
  EXPECT_NE(r.out.find("16384x16384"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("--tile-size"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("far field"), std::string::npos) << r.out;
}

// Without --max-distance a tiled bake takes its far horizons from the
// pyramid: in memory and in bands of rows (--low-memory, where the pyramid
// is built in the checksum pass) the same folder bit for bit, close to the
// single-file bake with unlimited distance, and resumable.
TEST(AalBakeTiled, WithoutMaxDistanceTheFarFieldCompletesTheHorizons) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 150, 120);
  const std::string options = " --azimuths 16 -q";
  const fs::path single = dir.path() / "a.exr", memory = dir.path() / "memory",
                 bands = dir.path() / "bands";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(single) + options).exitCode, 0);
  const auto r =
      runTool("aal-bake", quoted(dem) + " -o " + quoted(memory) + " --tile-size 16" + options);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const auto b = runTool("aal-bake", quoted(dem) + " -o " + quoted(bands) +
                                         " --tile-size 16 --low-memory --azimuths 16");
  ASSERT_EQ(b.exitCode, 0) << b.out;
  EXPECT_NE(b.out.find("16-texel tiles read in windows (80 baked"), std::string::npos) << b.out;
  const ApertureMap a = readApertureMap(single.string());
  const ApertureMap m = readApertureMap(memory.string()), n = readApertureMap(bands.string());
  EXPECT_EQ(m.texels, n.texels);
  EXPECT_NE(m.info.method.find("far-field"), std::string::npos) << m.info.method;
  double visible = 0.0;
  for (size_t i = 0; i < a.texelCount(); ++i) {
    visible += std::abs(a.visibleFraction(i) - m.visibleFraction(i));
  }
  EXPECT_LE(visible / a.texelCount(), 0.002);
  // Resumed: a tile removed is baked again, to the same pixels.
  fs::remove(memory / "index.txt");
  fs::remove(memory / apertureTileName(3, 4));
  const auto again =
      runTool("aal-bake", quoted(dem) + " -o " + quoted(memory) + " --tile-size 16 --azimuths 16");
  ASSERT_EQ(again.exitCode, 0) << again.out;
  EXPECT_NE(again.out.find("(1 baked, 79 resumed)"), std::string::npos) << again.out;
  EXPECT_EQ(readApertureMap(memory.string()).texels, m.texels);
}

std::vector<float> pixels(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> values(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, values.data())) return {};
  return values;
}

TEST(AalBakeTiled, RenderReadsTheTileFolder) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 90, 70), other = writeDem(dir, 90, 70, 2);
  const auto [single, folder] = bakeSingleAndTiled(dir, dem);
  ASSERT_FALSE(single.empty());
  const std::string view = " --size 64x48 --sun-azimuth 135 --sun-elevation 20";
  const fs::path fromFile = dir.path() / "file.exr", fromTiles = dir.path() / "tiles.exr";
  auto r = runTool("aal-render", quoted(dem) + " --aperture " + quoted(single) + " -o " +
                                     quoted(fromFile) + view);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  r = runTool("aal-render",
              quoted(dem) + " --aperture " + quoted(folder) + " -o " + quoted(fromTiles) + view);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const std::vector<float> a = pixels(fromFile), b = pixels(fromTiles);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
  // A folder baked from another DEM is refused.
  r = runTool("aal-render", quoted(other) + " --aperture " + quoted(folder) + " -o " +
                                quoted(dir.path() / "x.png") + view);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("does not belong"), std::string::npos) << r.out;
}

TEST(AalBakeTiled, ViewerReadsTheTileFolder) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 90, 70);
  const auto [single, folder] = bakeSingleAndTiled(dir, dem);
  ASSERT_FALSE(single.empty());
  const fs::path fromFile = dir.path() / "file.png", fromTiles = dir.path() / "tiles.png";
  const std::string flight = " --size 160x120 --frames 2 --screenshot ";
  auto r =
      test::runViewer(quoted(dem) + " --aperture " + quoted(single) + flight + quoted(fromFile));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  r = test::runViewer(quoted(dem) + " --aperture " + quoted(folder) + flight + quoted(fromTiles));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.out.find("aperture map ready"), std::string::npos) << "baked instead: " << r.out;
  const std::vector<float> a = pixels(fromFile), b = pixels(fromTiles);
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, b);
}

// A second aal-bake into a folder that a running one
// holds exits with 1 (the folder is busy: run it again later), before it
// reads the DEM, touching nothing; in memory and in bands alike.
TEST(AalBakeTiled, ABusyFolderExitsWithOneTouchingNothing) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 90, 70);
  const fs::path folder = dir.path() / "a.tiles";
  const std::string command = quoted(dem) + " -o " + quoted(folder) + " --tile-size 32" + kOptions;
  ASSERT_EQ(runTool("aal-bake", command).exitCode, 0);
  // As a running bake leaves it: some tiles, no index yet.
  fs::remove(folder / "index.txt");
  fs::remove(folder / apertureTileName(2, 2));
  const int lock = ::open((folder / ".aal-bake.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(lock, 0);
  ASSERT_EQ(::flock(lock, LOCK_EX | LOCK_NB), 0);
  const auto before = test::folderContents(folder);
  for (const char* how : {"", " --low-memory"}) {
    const auto r = runTool("aal-bake", command + how);
    EXPECT_EQ(r.exitCode, 1) << how << "\n" << r.out;
    EXPECT_NE(r.out.find("another aal-bake"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(folder.string()), std::string::npos) << r.out;
    EXPECT_EQ(test::changedFiles(before, test::folderContents(folder)), std::vector<std::string>{})
        << how;
  }
  ::close(lock);
  const auto r = runTool("aal-bake", command);
  EXPECT_EQ(r.exitCode, 0) << r.out;
  EXPECT_TRUE(fs::exists(folder / "index.txt"));
}

// A bake of another DEM into a folder holding a bake is refused (exit 2),
// saying whose bake the folder holds, and leaves its files as they were.
TEST(AalBakeTiled, AFolderOfAnotherDemExitsWithTwoTouchingNothing) {
  TempDir dir;
  const fs::path first = writeDem(dir, 90, 70, 1), second = writeDem(dir, 90, 70, 2);
  const fs::path folder = dir.path() / "a.tiles";
  ASSERT_EQ(
      runTool("aal-bake", quoted(first) + " -o " + quoted(folder) + " --tile-size 32" + kOptions)
          .exitCode,
      0);
  // Finished; interrupted; interrupted before manifests existed, its first
  // tile unreadable (which the bake of the other DEM used to bake again as
  // its own, taking the folder over).
  for (const int state : {0, 1, 2}) {
    if (state == 1) fs::remove(folder / "index.txt");
    if (state == 2) {
      fs::remove(folder / "manifest.txt");
      fs::resize_file(folder / apertureTileName(0, 0), 100);
    }
    const auto before = test::folderContents(folder);
    for (const char* how : {"", " --low-memory"}) {
      const auto r = runTool("aal-bake", quoted(second) + " -o " + quoted(folder) +
                                             " --tile-size 32" + kOptions + how);
      EXPECT_EQ(r.exitCode, 2) << how << "\n" << r.out;
      EXPECT_NE(r.out.find(state == 2 ? "another tiled bake" : "another DEM"), std::string::npos)
          << r.out;
      EXPECT_NE(r.out.find(": dem1.tif, 90x70, heights checksum"), std::string::npos) << r.out;
      if (state == 2) {
        EXPECT_NE(r.out.find("tile_0000_0001.exr"), std::string::npos) << r.out;
      }
      EXPECT_NE(r.out.find("another folder"), std::string::npos) << r.out;
      EXPECT_EQ(test::changedFiles(before, test::folderContents(folder)),
                std::vector<std::string>{})
          << how;
    }
  }
}

}  // namespace
}  // namespace aal
