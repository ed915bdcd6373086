// Command-line contract of aal-info and aal-synth.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

using test::runTool;

const std::string kJacksboro =
    std::string(AAL_TEST_SOURCE_DIR) + "/heightmaps/jacksboro_fault_dem.tif";

// The raw text of a top-level value in a one-line JSON object ("<missing>"
// when the key is absent). Plain string scanning: GCC 12 with ASan warns
// about std::regex internals.
std::string jsonValue(const std::string& json, const std::string& key) {
  const std::string marker = "\"" + key + "\": ";
  const size_t start = json.find(marker);
  if (start == std::string::npos) return "<missing>";
  size_t end = start + marker.size();
  int depth = 0;
  bool quoted = false;
  for (; end < json.size(); ++end) {
    const char c = json[end];
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    if (depth == 0 && (c == ',' || c == '}')) break;
    if (c == '[' || c == '{') ++depth;
    if (c == ']' || c == '}') --depth;
  }
  return json.substr(start + marker.size(), end - start - marker.size());
}

double jsonNumber(const std::string& json, const std::string& key) {
  return std::stod(jsonValue(json, key));
}

// The first line of the output that starts with '{'.
std::string jsonLine(const std::string& out) {
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    if (!line.empty() && line[0] == '{') return line;
  }
  return "";
}

TEST(AalInfo, JsonHasEveryKeyForJacksboro) {
  const auto r = runTool("aal-info", "'" + kJacksboro + "' --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const std::string json = jsonLine(r.out);
  ASSERT_FALSE(json.empty()) << r.out;
  EXPECT_EQ(json.back(), '}');
  for (const char* key :
       {"format", "driver", "width", "height", "crs", "crs_name", "epsg", "cell_size_m",
        "center_lat", "center_lon", "nodata", "units", "z_scale", "z_min", "z_max", "voids"}) {
    EXPECT_NE(jsonValue(json, key), "<missing>") << key << " in " << json;
  }
  EXPECT_EQ(jsonValue(json, "format"), "\"GeoTIFF\"");
  EXPECT_EQ(jsonNumber(json, "width"), 403);
  EXPECT_EQ(jsonNumber(json, "height"), 344);
  EXPECT_EQ(jsonValue(json, "crs"), "\"geographic\"");
  EXPECT_EQ(jsonNumber(json, "epsg"), 4326);
  const std::string cellText = jsonValue(json, "cell_size_m");
  double cellX = 0, cellY = 0;
  ASSERT_EQ(std::sscanf(cellText.c_str(), "[%lf, %lf]", &cellX, &cellY), 2) << cellText;
  EXPECT_NEAR(cellX, 74.57, 0.02);
  EXPECT_NEAR(cellY, 92.47, 0.02);
  EXPECT_NEAR(jsonNumber(json, "center_lat"), 36.589583, 1e-6);
  EXPECT_NEAR(jsonNumber(json, "center_lon"), -84.245833, 1e-6);
  EXPECT_LT(jsonNumber(json, "z_min"), jsonNumber(json, "z_max"));
  EXPECT_EQ(jsonNumber(json, "voids"), 0);
  EXPECT_EQ(jsonValue(json, "driver"), "\"GTiff\"");
  EXPECT_EQ(jsonValue(json, "crs_name"), "\"WGS 84\"");
  EXPECT_EQ(jsonNumber(json, "nodata"), -32768);
  EXPECT_EQ(jsonValue(json, "units"), "{\"horizontal\": \"degree\", \"vertical\": null}");
}

TEST(AalInfo, TextGivesRowRangeOfGeographicCellSizes) {
  const auto r = runTool("aal-info", "'" + kJacksboro + "'");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  for (const char* part : {"format     GeoTIFF", "size       403 x 344", "EPSG:4326",
                           "over the rows", "lat 36.589583, lon -84.245833", "voids      0"}) {
    EXPECT_NE(r.out.find(part), std::string::npos) << part << " in\n" << r.out;
  }
}

TEST(AalInfo, OverridesReplaceTheFilesValues) {
  const auto r = runTool("aal-info", "'" + kJacksboro + "' --json --cell-size 10 --z-scale 2");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const std::string json = jsonLine(r.out);
  EXPECT_EQ(jsonValue(json, "cell_size_m"), "[10, 10]");
  const auto plain = runTool("aal-info", "'" + kJacksboro + "' --json");
  EXPECT_DOUBLE_EQ(jsonNumber(json, "z_max"), 2 * jsonNumber(jsonLine(plain.out), "z_max"));
}

TEST(AalInfo, UngeoreferencedDemWarnsAndHasNullCentre) {
  test::TempDir dir;
  const std::string path = (dir.path() / "g.asc").string();
  std::ofstream(path) << "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 5\n1 2\n3 -9\n";
  auto r = runTool("aal-info", "'" + path + "' --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(jsonValue(jsonLine(r.out), "epsg"), "null");
  EXPECT_EQ(jsonValue(jsonLine(r.out), "center_lat"), "null");
  EXPECT_EQ(jsonValue(jsonLine(r.out), "crs"), "\"projected\"");
}

TEST(AalInfo, PlainImageWarnsAboutAssumedScale) {
  test::TempDir dir;
  const std::string tif = (dir.path() / "plain.tif").string();
  const std::vector<float> z = {1, 2, 3, 4, 5, 6};
  writeFloatGeoTiff(tif, 3, 2, z.data(), GeoReference{});
  const auto r = runTool("aal-info", "'" + tif + "' --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("aal-info: warning: " + tif + " is not georeferenced"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("--cell-size"), std::string::npos) << r.out;
  EXPECT_EQ(jsonValue(jsonLine(r.out), "crs"), "\"none\"");
  EXPECT_EQ(jsonValue(jsonLine(r.out), "format"), "\"GeoTIFF\"");
  EXPECT_EQ(jsonValue(jsonLine(r.out), "driver"), "\"GTiff\"");
  EXPECT_EQ(jsonValue(jsonLine(r.out), "nodata"), "null");
}

TEST(AalInfo, UnknownContentExitsWithTwo) {
  test::TempDir dir;
  const std::string path = (dir.path() / "notes.txt").string();
  std::ofstream(path, std::ios::binary) << "not elevation data at all\n";
  const auto r = runTool("aal-info", "'" + path + "'");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.out.find(path + ": not a raster GDAL can read"), std::string::npos) << r.out;
}

TEST(AalInfo, BadInputExitsWithTwoAndNamesTheFile) {
  test::TempDir dir;
  const std::string asc = (dir.path() / "bad.asc").string();
  std::ofstream(asc) << "ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\n1 2\n";  // no cellsize
  const std::string hgt = (dir.path() / "N10E010.hgt").string();
  std::ofstream(hgt) << "too short";
  const std::string missing = (dir.path() / "missing.tif").string();
  struct Case {
    std::string arguments, message;
  };
  for (const Case& c : {Case{"'" + missing + "'", "no such file"},
                        Case{"'" + asc + "'", asc + ": not a raster GDAL can read"},
                        Case{"'" + hgt + "'", hgt + ": not a raster GDAL can read"},
                        Case{"'" + kJacksboro + "' --cell-size -1", "--cell-size"},
                        Case{"'" + kJacksboro + "' --z-scale 0", "--z-scale"}}) {
    const auto r = runTool("aal-info", c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << r.out;
    EXPECT_EQ(jsonLine(r.out), "");
  }
  EXPECT_EQ(runTool("aal-info", "").exitCode, 2);  // DEM is required
}

TEST(AalInfo, ReadsInBandsWithinAMemoryLimitThatRefusesAWholeLoad) {
  // Jacksboro's heights and void mask take 693 kB; aal-info needs a band.
  const std::string limit = "AAL_MEMORY_LIMIT=300K";
  const auto info = runTool("aal-info", "'" + kJacksboro + "' --json", limit);
  ASSERT_EQ(info.exitCode, 0) << info.out;
  const auto whole = runTool("aal-info", "'" + kJacksboro + "' --json");
  EXPECT_EQ(jsonLine(info.out), jsonLine(whole.out));
  const auto render =
      runTool("aal-render", "'" + kJacksboro + "' --mode reference -o x.png", limit);
  EXPECT_EQ(render.exitCode, 2) << render.out;
  // The ray tracer's whole run, 8 bytes per texel, is what is checked.
  EXPECT_NE(render.out.find("holding a ray-traced render of its 403 x 344 texels (8 bytes per "
                            "texel) needs 1.1 MB, but only 307 kB"),
            std::string::npos)
      << render.out;
}

TEST(AalSynth, WritesAGeoTiffThatLoadsBackExactly) {
  test::TempDir dir;
  const std::string path = (dir.path() / "synth.tif").string();
  const auto r =
      runTool("aal-synth", "-o '" + path + "' --size 64 --seed 3 --cell-size 10 --ridged");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Heightfield f = loadDem(path);
  SyntheticTerrainOptions o;
  o.width = o.height = 64;
  o.seed = 3;
  o.cellSizeM = 10;
  o.ridged = true;
  EXPECT_EQ(f.z, makeSyntheticTerrain(o).z);
  EXPECT_EQ(f.geo.crs, CrsKind::Projected);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 10.0);
  EXPECT_DOUBLE_EQ(f.geo.originX, 5.0);  // south-west corner at (0, 0)
  EXPECT_DOUBLE_EQ(f.geo.originY, 635.0);

  const auto info = runTool("aal-info", "'" + path + "' --json");
  ASSERT_EQ(info.exitCode, 0) << info.out;
  EXPECT_EQ(jsonValue(jsonLine(info.out), "cell_size_m"), "[10, 10]");
  EXPECT_EQ(info.out.find("warning"), std::string::npos) << info.out;
}

TEST(AalSynth, NonFiniteNumbersExitWithTwo) {
  test::TempDir dir;
  const std::string out = (dir.path() / "x.tif").string();
  for (const std::string args : {"--size 16 --amplitude nan", "--size 16 --cell-size nan"}) {
    const auto r = runTool("aal-synth", "-o '" + out + "' " + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("every number must be finite"), std::string::npos) << r.out;
  }
  EXPECT_FALSE(std::filesystem::exists(out));
  const auto info = runTool("aal-info", "'" + kJacksboro + "' --z-scale nan");
  EXPECT_EQ(info.exitCode, 2) << info.out;
  EXPECT_NE(info.out.find("--z-scale nan"), std::string::npos) << info.out;
}

TEST(AalSynth, SeedsDecideTheHeights) {
  test::TempDir dir;
  const auto write = [&](const std::string& name, int seed) {
    const std::string path = (dir.path() / name).string();
    EXPECT_EQ(
        runTool("aal-synth", "-o '" + path + "' --size 32 --seed " + std::to_string(seed)).exitCode,
        0);
    return loadDem(path).z;
  };
  EXPECT_EQ(write("a.tif", 5), write("b.tif", 5));
  EXPECT_NE(write("a.tif", 5), write("c.tif", 6));
}

TEST(AalSynth, BadArgumentsFailWithoutOutput) {
  test::TempDir dir;
  EXPECT_EQ(runTool("aal-synth", "-o '" + (dir.path() / "x.tif").string() + "'").exitCode, 2);
  EXPECT_EQ(runTool("aal-synth", "-o '" + (dir.path() / "x.tif").string() + "' --size 0").exitCode,
            2);
  const auto r = runTool("aal-synth", "-o '" + (dir.path() / "no/x.tif").string() + "' --size 8");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::is_empty(dir.path()));
}

}  // namespace
}  // namespace aal
