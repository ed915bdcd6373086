// aal-bake --local-dominance: the raster and its refusals.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>

#include <chrono>
#include <filesystem>
#include <string>
#include <thread>

#include "aperture/preprocess/local_dominance.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

// A width x height (48 x 40) fBm DEM of 1 m cells (lidar-like relief) in
// UTM 16N, with a void of 2 x 3 texels at (30, 5).
fs::path writeDem(const TempDir& dir, int width = 48, int height = 40) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 1;
  s.amplitudeM = 8;
  s.featureSizeTexels = 12;
  Heightfield field = makeSyntheticTerrain(s);
  for (int row = 5; row < 8; ++row) {
    for (int col = 30; col < 32; ++col) field.z[field.index(col, row)] = -9999.0f;
  }
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500000;
  geo.originY = 4000000;
  geo.stepX = geo.stepY = 1;
  RasterWriteOptions options;
  options.nodata = -9999.0;
  const fs::path path = dir.path() / "dem.tif";
  writeFloatGeoTiff(path.string(), width, height, field.z.data(), geo, options);
  return path;
}

TEST(AalBakeLocalDominance, WritesTheRasterPlacedLikeTheDem) {
  TempDir dir;
  const fs::path dem = writeDem(dir), ld = dir.path() / "ld.tif";
  const auto r =
      runTool("aal-bake", quoted(dem) + " -q --azimuths 8 -o " + quoted(dir.path() / "a.exr") +
                              " --local-dominance " + quoted(ld) +
                              " --local-dominance-radii 4 9 --observer-height 1.2");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Heightfield field = loadDem(dem.string());
  const std::vector<float> expected =
      localDominance(field, {.minRadiusCells = 4, .maxRadiusCells = 9, .observerHeightM = 1.2});
  const Heightfield written = loadDem(ld.string());
  EXPECT_EQ(written.geo.epsg, 32616);
  ASSERT_EQ(written.width, 48);
  ASSERT_EQ(written.height, 40);
  size_t voids = 0;
  for (int row = 0; row < 40; ++row) {
    for (int col = 0; col < 48; ++col) {
      const bool isVoid = row >= 5 && row < 8 && col >= 30 && col < 32;
      ASSERT_EQ(written.isVoid(col, row), isVoid) << col << "," << row;
      voids += isVoid;
      if (!isVoid) {
        ASSERT_EQ(written.at(col, row), expected[field.index(col, row)]) << col << "," << row;
      }
    }
  }
  EXPECT_EQ(voids, 6u);
}

TEST(AalBakeLocalDominance, RefusalsExitWithTwoAndWriteNothing) {
  TempDir dir;
  const fs::path dem = writeDem(dir);
  const std::string in = quoted(dem) + " -q -o " + quoted(dir.path() / "a.exr");
  const std::string ld = " --local-dominance " + quoted(dir.path() / "ld.tif");
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {
           Case{quoted(dem) + " -q -o " + quoted(dir.path() / "tiles") + " --tile-size 16" + ld,
                "--local-dominance: bake them in one piece"},
           Case{in + ld + " --local-dominance-radii 9 4", "inner radius must not exceed"},
           Case{in + ld + " --local-dominance-radii 0 4", "--local-dominance-radii"},
           Case{in + ld + " --observer-height -1", "--observer-height"},
           Case{in + " --local-dominance-radii 4 9", "requires --local-dominance"},
           Case{in + " --observer-height 2", "requires --local-dominance"},
           Case{in + ld + " --svf " + quoted(dir.path() / "ld.tif"), "is also the output of"},
       }) {
    const auto r = runTool("aal-bake", c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << "\n" << r.out;
  }
  for (const char* name : {"a.exr", "ld.tif", "tiles"}) {
    EXPECT_FALSE(fs::exists(dir.path() / name)) << name;
  }
}

// Ctrl-C while local dominance runs (after the bake) stops it cleanly: exit
// 1, not the watchdog's 128 + SIGINT, and nothing written.
TEST(AalBakeLocalDominance, InterruptLeavesNoFile) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 512, 512);
  const std::string out = (dir.path() / "a.exr").string(), ld = (dir.path() / "ld.tif").string();
  // A ring of 24 x 1000 samples per texel of 512²: a minute of work after a
  // bake of a few milliseconds.
  EXPECT_EQ(test::interruptMidRun(
                "aal-bake", {dem.string(), "-o", out, "--azimuths", "4", "-q", "--local-dominance",
                             ld, "--local-dominance-radii", "1", "1000"}),
            1);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(ld));
}

}  // namespace
}  // namespace aal
