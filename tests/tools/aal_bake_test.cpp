// Command-line contract of aal-bake.
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::runTool;
using test::TempDir;

using test::quoted;
// A synthetic DEM written as a projected float GeoTIFF.
fs::path writeDem(const TempDir& dir, int size, const std::string& name = "dem.tif") {
  SyntheticTerrainOptions s;
  s.width = s.height = size;
  s.cellSizeM = 30;
  s.featureSizeTexels = size / 4.0;
  const Heightfield field = makeSyntheticTerrain(s);
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;  // UTM 16N
  geo.originX = 500000;
  geo.originY = 4000000;
  geo.stepX = geo.stepY = 30;
  const fs::path path = dir.path() / name;
  writeFloatGeoTiff(path.string(), size, size, field.z.data(), geo);
  return path;
}

size_t filesIn(const fs::path& dir) {
  size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

TEST(AalBake, WritesTheApertureMapAndExtras) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 48);
  const fs::path out = dir.path() / "a.exr", svf = dir.path() / "svf.tif",
                 visible = dir.path() / "vis.tif";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(out) + " --azimuths 16 --svf " +
                                         quoted(svf) + " --visible " + quoted(visible));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("48x48"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("16 azimuths"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("texel-azimuths/s"), std::string::npos) << r.out;

  const ApertureMap map = readApertureMap(out.string());
  EXPECT_EQ(map.info.azimuths, 16);
  EXPECT_EQ(map.info.source, "dem.tif");
  EXPECT_FLOAT_EQ(map.info.cellSizeX, 30.0f);
  const Heightfield field = loadDem(dem.string());
  EXPECT_NO_THROW(checkApertureMatchesDem(map, out.string(), field, dem.string()));

  // The extras carry the DEM's georeferencing and agree with the map.
  const Heightfield vis = loadDem(visible.string());
  EXPECT_EQ(vis.geo.epsg, 32616);
  EXPECT_EQ(vis.width, 48);
  for (size_t i = 0; i < vis.texelCount(); ++i) {
    ASSERT_NEAR(vis.z[i], map.visibleFraction(i), 2e-3) << i;  // map stores halves
  }
  const Heightfield sky = loadDem(svf.string());
  for (float v : sky.z) {
    ASSERT_GE(v, 0.0f);
    ASSERT_LE(v, 1.0f);
  }
  EXPECT_EQ(filesIn(dir.path()), 4u);  // dem + three outputs, no temporaries
}

// Without -o a bake writes only the rasters asked for (as SAGA would), the
// same bytes as beside a map; with nothing to write, or tiled without a
// folder, it is refused before any work.
TEST(AalBake, RastersAloneNeedNoMap) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 48);
  const fs::path withMap = dir.path() / "with_map.tif", alone = dir.path() / "alone.tif";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -q --azimuths 16 -o " +
                                    quoted(dir.path() / "a.exr") + " --svf " + quoted(withMap))
                .exitCode,
            0);
  const auto r = runTool("aal-bake", quoted(dem) + " --azimuths 16 --svf " + quoted(alone));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("-> " + alone.string()), std::string::npos) << r.out;
  const auto bytes = [](const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  EXPECT_EQ(bytes(alone), bytes(withMap));
  EXPECT_EQ(filesIn(dir.path()), 4u);  // dem, a.exr and the two rasters: no map beside alone.tif

  const auto nothing = runTool("aal-bake", quoted(dem) + " --azimuths 16");
  EXPECT_EQ(nothing.exitCode, 2) << nothing.out;
  EXPECT_NE(nothing.out.find("nothing to write"), std::string::npos) << nothing.out;
  const auto tiled =
      runTool("aal-bake", quoted(dem) + " --tile-size 32 --svf " + quoted(dir.path() / "t.tif"));
  EXPECT_EQ(tiled.exitCode, 2) << tiled.out;
  EXPECT_NE(tiled.out.find("give -o FOLDER"), std::string::npos) << tiled.out;
  EXPECT_EQ(filesIn(dir.path()), 4u);
}

// Rasters alone (no map) are baked in memory up to 32768 x 32768 texels,
// twice the map's side, when the memory check lets them: a 20000 x 20000
// DEM (a VRT over a small GeoTIFF) meets the memory check, not the tiling
// the map would need; above 32768 x 32768 a tiled bake is asked for.
TEST(AalBake, RastersAloneStayInMemoryToTwiceTheMapsSide) {
  TempDir dir;
  writeDem(dir, 64, "small.tif");
  const auto vrt = [&](int side) {
    const fs::path path = dir.path() / ("big" + std::to_string(side) + ".vrt");
    std::ofstream(path) << "<VRTDataset rasterXSize=\"" << side << "\" rasterYSize=\"" << side
                        << "\">\n  <SRS>EPSG:32616</SRS>\n"
                        << "  <GeoTransform>500000, 30, 0, 4000000, 0, -30</GeoTransform>\n"
                        << "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
                        << "    <SimpleSource><SourceFilename relativeToVRT=\"1\">small.tif"
                        << "</SourceFilename>\n      <SourceBand>1</SourceBand>\n"
                        << "    </SimpleSource>\n  </VRTRasterBand>\n</VRTDataset>\n";
    return path;
  };
  const std::string svf = " --svf " + quoted(dir.path() / "svf.tif") + " -q";
  const auto alone = runTool("aal-bake", quoted(vrt(20000)) + svf, "AAL_MEMORY_LIMIT=100M");
  EXPECT_EQ(alone.exitCode, 2) << alone.out;
  EXPECT_NE(alone.out.find("holding its bake in memory (10 bytes per texel) needs 4.00 GB"),
            std::string::npos)
      << alone.out;
  const auto map =
      runTool("aal-bake", quoted(vrt(20000)) + " -o " + quoted(dir.path() / "a.exr") + svf,
              "AAL_MEMORY_LIMIT=100M");
  EXPECT_EQ(map.exitCode, 2) << map.out;
  EXPECT_NE(map.out.find("above 16384x16384 texels only a tiled bake fits in memory"),
            std::string::npos)
      << map.out;
  const auto larger = runTool("aal-bake", quoted(vrt(33000)) + svf);
  EXPECT_EQ(larger.exitCode, 2) << larger.out;
  EXPECT_NE(larger.out.find("give -o FOLDER (the DEM is above 32768x32768 texels"),
            std::string::npos)
      << larger.out;
  EXPECT_FALSE(fs::exists(dir.path() / "svf.tif"));
}

// --horizons writes the directional horizons of the same bake (docs/baking.md).
TEST(AalBake, WritesTheDirectionalHorizons) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 40);
  const fs::path out = dir.path() / "a.exr", horizons = dir.path() / "a.horizons";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(out) + " --azimuths 16 " +
                                         "--horizons " + quoted(horizons) + " -q");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const HorizonMap map = readHorizonMap(horizons);
  EXPECT_EQ(map.width, 40);
  EXPECT_EQ(map.height, 40);
  // 16 directions of 8 bits by default (kBakeToolHorizonDirections, ...Bits).
  EXPECT_EQ(map.directions, 16);
  EXPECT_EQ(map.bits, 8);
  BakeOptions o;
  o.azimuths = 16;
  o.horizons = true;
  o.horizonDirections = 16;
  o.horizonBits = 8;
  EXPECT_EQ(map.codes, bakeApertures(loadDem(dem.string()), o).horizons.codes);
  // 8 directions of 4 bits when asked.
  const fs::path eight = dir.path() / "eight.horizons";
  const auto r8 = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "c.exr") +
                                          " --azimuths 16 --horizon-directions 8 --horizon-bits 4 "
                                          "--horizons " +
                                          quoted(eight) + " -q");
  ASSERT_EQ(r8.exitCode, 0) << r8.out;
  const HorizonMap eightMap = readHorizonMap(eight);
  EXPECT_EQ(eightMap.bits, 4);
  EXPECT_EQ(eightMap.directions, 8);
  o.horizonDirections = 8;
  o.horizonBits = 4;
  EXPECT_EQ(eightMap.codes, bakeApertures(loadDem(dem.string()), o).horizons.codes);
  // Horizons the bake cannot give, or that would overwrite another output.
  for (const std::string& args :
       {" --azimuths 12 --horizons " + quoted(dir.path() / "h1"),
        " --horizon-bits 6 --horizons " + quoted(dir.path() / "h1"),
        " --method rays --horizons " + quoted(dir.path() / "h2"),
        " --horizons " + quoted(dir.path() / "b.exr"),  // the -o of the same run
        " --tile-size 16 --max-distance 100 --horizons " + quoted(dir.path() / "h3")}) {
    const auto bad = runTool(
        "aal-bake",
        quoted(dem) + " -o " +
            quoted(dir.path() / (args.find("tile") != std::string::npos ? "tiles" : "b.exr")) +
            args);
    EXPECT_EQ(bad.exitCode, 2) << args << "\n" << bad.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "h1"));
}

TEST(AalBake, QuietPrintsNothing) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 16);
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " -q");
  EXPECT_EQ(r.exitCode, 0);
  EXPECT_EQ(r.out, "");
}

std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// `aal-bake d.tif -o d.tif` must not turn the DEM into an aperture map
// (exit 0), nor `-o a.tif` write a map nothing reads.
TEST(AalBake, OutputsThatAreInputsOrEachOtherOrNotExrExitWithTwo) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 16);
  const std::string before = bytesOf(dem);
  fs::create_symlink(dem, dir.path() / "link.exr");
  fs::create_hard_link(dem, dir.path() / "hard.exr");
  const std::string in = quoted(dem) + " -q ";
  struct Case {
    std::string args, says;
  };
  for (const Case& c :
       {Case{"-o " + quoted(dem), "is the input DEM"},
        Case{"-o " + quoted(dir.path() / "link.exr"), "is the input DEM"},
        Case{"-o " + quoted(dir.path() / "hard.exr"), "is the input DEM"},
        Case{"-o " + quoted(dir.path() / "." / "dem.tif"), "is the input DEM"},
        Case{"-o " + quoted(dir.path() / "b.exr") + " --svf " + quoted(dir.path() / "b.exr"),
             "is also the output of -o"},
        Case{"-o " + quoted(dir.path() / "c.exr") + " --svf " + quoted(dir.path() / "s.tif") +
                 " --visible " + quoted(dir.path() / "s.tif"),
             "is also the output of --svf"},
        Case{"-o " + quoted(dir.path() / "a.png"), "OpenEXR file (.exr), a GeoTIFF"},
        Case{"-o " + quoted(dir.path() / "a"), "OpenEXR file (.exr)"}}) {
    const auto r = runTool("aal-bake", in + c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << "\n" << r.out;
  }
  EXPECT_EQ(bytesOf(dem), before);
  for (const char* name : {"a.png", "a", "b.exr", "c.exr", "s.tif"}) {
    EXPECT_FALSE(fs::exists(dir.path() / name)) << name;
  }
  EXPECT_EQ(runTool("aal-bake", in + "-o " + quoted(dir.path() / "UPPER.EXR")).exitCode, 0);
}

TEST(AalBake, NonFiniteNumbersExitWithTwoBeforeWork) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 16);
  for (const std::string args :
       {"--max-distance nan", "--refraction nan --curvature", "--cell-size nan"}) {
    const auto r =
        runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " " + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("every number must be finite"), std::string::npos) << r.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

TEST(AalBake, JacksboroBakesWithoutNan) {
  TempDir dir;
  const fs::path out = dir.path() / "j.exr";
  const fs::path dem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(out) + " --float");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const ApertureMap map = readApertureMap(out.string());
  EXPECT_EQ(map.info.source, "jacksboro_fault_dem.tif");
  EXPECT_EQ(map.info.method, "sweep");
  EXPECT_EQ(map.info.azimuths, 64);
  EXPECT_NEAR(map.info.cellSizeY, 92.5, 0.5);  // 3 arc-seconds of latitude
  for (size_t i = 0; i < map.texelCount(); ++i) {
    const float* t = &map.texels[4 * i];
    ASSERT_TRUE(std::isfinite(t[0]) && std::isfinite(t[1]) && std::isfinite(t[2]) &&
                std::isfinite(t[3]))
        << i;
    ASSERT_NEAR(t[0] * t[0] + t[1] * t[1] + t[2] * t[2], 1.0f, 1e-4f);
    ASSERT_GE(t[3], 0.0f);
    ASSERT_LE(t[3], 1.5708f);
  }
}

TEST(AalBake, BadArgumentsExitWithTwo) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 16);
  const std::string out = " -o " + quoted(dir.path() / "a.exr");
  for (const std::string& args :
       {quoted(dem) + out + " --azimuths 3", quoted(dem) + out + " --azimuths 100000",
        quoted(dem) + out + " --method magic", quoted(dem) + out + " --edge wrap",
        quoted(dem) + out + " --max-distance -5", quoted(dem) + out + " --cell-size 0", quoted(dem),
        quoted(dir.path() / "missing.tif") + out,
        quoted(dem) + out + " --method rays --svf " + quoted(dir.path() / "s.tif")}) {
    const auto r = runTool("aal-bake", args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

TEST(AalBake, UnwritableOutputFailsBeforeBaking) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 16);
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "no" / "a.exr"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("texel-azimuths"), std::string::npos) << "baked anyway: " << r.out;
}

TEST(AalBake, ReplacesAnExistingOutput) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 16);
  const fs::path out = dir.path() / "a.exr";
  std::ofstream(out) << "old junk";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(out)).exitCode, 0);
  EXPECT_NO_THROW(readApertureMap(out.string()));
  EXPECT_EQ(filesIn(dir.path()), 2u);
}

TEST(AalBake, InterruptLeavesNoFile) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 512);
  const fs::path out = dir.path() / "a.exr";
  // Enough azimuths for tens of seconds of work; interrupted well before.
  EXPECT_EQ(test::interruptMidRun("aal-bake",
                                  {dem.string(), "-o", out.string(), "--azimuths", "4096", "-q"}),
            1);
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(filesIn(dir.path()), 1u);  // only the DEM: no temporary left behind
}

// A DEM read is interrupted too: GDAL's progress callback answers the flag
// block by block (terrain/io/gdal_session.h interruptibleRead), and the
// watchdog ends whatever does not unwind within a second. A VRT that blows
// a 64 x 64 GeoTIFF up to 8000 x 8000 takes seconds to read.
TEST(AalBake, InterruptStopsTheDemReadWithinASecond) {
  TempDir dir;
  const fs::path source = writeDem(dir, 64, "small.tif");
  const fs::path vrt = dir.path() / "big.vrt";
  {
    std::ofstream out(vrt);
    out << "<VRTDataset rasterXSize=\"8000\" rasterYSize=\"8000\">\n"
        << "  <SRS>EPSG:32616</SRS>\n"
        << "  <GeoTransform>500000, 0.25, 0, 4000000, 0, -0.25</GeoTransform>\n"
        << "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
        << "    <SimpleSource><SourceFilename relativeToVRT=\"1\">small.tif</SourceFilename>\n"
        << "      <SourceBand>1</SourceBand>\n"
        << "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"64\" ySize=\"64\"/>\n"
        << "      <DstRect xOff=\"0\" yOff=\"0\" xSize=\"8000\" ySize=\"8000\"/>\n"
        << "    </SimpleSource>\n  </VRTRasterBand>\n</VRTDataset>\n";
  }
  const fs::path out = dir.path() / "a.exr";
  const std::string bake = (test::binDir() / "aal-bake").string();
  const std::string demArg = vrt.string(), outArg = out.string();
  const char* argv[] = {bake.c_str(), demArg.c_str(), "-o", outArg.c_str(), "-q", nullptr};
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, bake.c_str(), nullptr, nullptr, const_cast<char**>(argv), environ),
            0);
  for (int i = 0; i < 200 && !test::catchesSignal(pid, SIGINT); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // reading by now
  const auto signalled = std::chrono::steady_clock::now();
  kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_NE(WEXITSTATUS(status), 0);
  EXPECT_LT(seconds, 1.0 + 0.5);  // 1 s, and a margin for a loaded machine
  EXPECT_FALSE(fs::exists(out));
  EXPECT_EQ(filesIn(dir.path()), 2u);  // the GeoTIFF and the VRT: no temporary
}

// The ray baker polls SIGTERM often: once per 1 % of rows would be minutes
// apart at 2^20 rays per texel (a 64^2 DEM: a row is ~30 s here).
// The bound below is for a loaded machine; it answers in ~0.1 s.
TEST(AalBake, RayBakeStopsSoonAfterSigterm) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 64);
  const fs::path out = dir.path() / "a.exr";
  const std::string bake = (test::binDir() / "aal-bake").string();
  const std::string demArg = dem.string(), outArg = out.string();
  const char* argv[] = {bake.c_str(), demArg.c_str(), "-o",      outArg.c_str(), "--method",
                        "rays",       "--rays",       "1048576", "-q",           nullptr};
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, bake.c_str(), nullptr, nullptr, const_cast<char**>(argv), environ),
            0);
  for (int i = 0; i < 200 && !test::catchesSignal(pid, SIGTERM); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const auto signalled = std::chrono::steady_clock::now();
  kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  EXPECT_LT(seconds, 10.0);
  EXPECT_EQ(filesIn(dir.path()), 1u);
}

}  // namespace
}  // namespace aal
