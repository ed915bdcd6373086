// Command-line contract of aal-relief: the GeoTIFF it writes, read back with
// GDAL (size, geotransform, CRS, nodata), and its values on planes against
// the closed forms (docs/relief.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <vector>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kCell = 10;
constexpr float kNodata = -9999;

// A plane rising `slopeDeg` to the east on a UTM grid of 10 m cells; the
// texel (voidCol, voidRow) is nodata when voidCol >= 0.
fs::path writePlane(const TempDir& dir, int size, double slopeDeg, int voidCol = -1,
                    int voidRow = -1, const std::string& name = "dem.tif") {
  std::vector<float> z(static_cast<size_t>(size) * size);
  for (int r = 0; r < size; ++r) {
    for (int c = 0; c < size; ++c) {
      z[static_cast<size_t>(r) * size + c] =
          static_cast<float>(100 + std::tan(slopeDeg * kDeg) * c * kCell);
    }
  }
  RasterWriteOptions options;
  if (voidCol >= 0) {
    z[static_cast<size_t>(voidRow) * size + voidCol] = kNodata;
    options.nodata = kNodata;
  }
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500005;
  geo.originY = 4000005;
  geo.stepX = geo.stepY = kCell;
  const fs::path path = dir.path() / name;
  writeFloatGeoTiff(path.string(), size, size, z.data(), geo, options);
  return path;
}

struct Raster {
  int width = 0, height = 0, bands = 0;
  double transform[6] = {};
  OGRSpatialReference crs;
  bool hasNodata = false;
  double nodata = 0;
  GDALDataType type = GDT_Unknown;
  std::vector<std::vector<double>> samples;  // per band, row-major
  double at(int band, int x, int y) const {
    return samples[static_cast<size_t>(band)][static_cast<size_t>(y) * width + x];
  }
};

Raster readRaster(const fs::path& path) {
  ensureGdal();
  Raster r;
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
  if (!ds) {
    ADD_FAILURE() << "GDAL cannot open " << path;
    return r;
  }
  r.width = ds->GetRasterXSize();
  r.height = ds->GetRasterYSize();
  r.bands = ds->GetRasterCount();
  EXPECT_EQ(ds->GetGeoTransform(r.transform), CE_None);
  if (ds->GetSpatialRef()) r.crs = *ds->GetSpatialRef();
  int has = 0;
  r.nodata = ds->GetRasterBand(1)->GetNoDataValue(&has);
  r.hasNodata = has != 0;
  r.type = ds->GetRasterBand(1)->GetRasterDataType();
  for (int b = 1; b <= r.bands; ++b) {
    std::vector<double> v(static_cast<size_t>(r.width) * r.height);
    EXPECT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Read, 0, 0, r.width, r.height, v.data(), r.width,
                                             r.height, GDT_Float64, 0, 0, nullptr),
              CE_None);
    r.samples.push_back(std::move(v));
  }
  return r;
}

std::string cacheEnv(const TempDir& dir) {
  return "AAL_CACHE_DIR=" + quoted(dir.path() / "cache");
}

// Sun alone (k = 0) on flat ground: sin e, placed exactly like the DEM.
TEST(AalRelief, FlatPlaneIsSinOfTheElevationAndPlacedLikeTheDem) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 32, 0), out = dir.path() / "relief.tif";
  for (const double e : {30.0, 60.0}) {
    const auto r = runTool("aal-relief",
                           quoted(dem) + " -o " + quoted(out) +
                               " --format float --sky 0 --sun-elevation " + std::to_string(e),
                           cacheEnv(dir));
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_NE(r.out.find("wrote"), std::string::npos) << r.out;
    const Raster relief = readRaster(out), source = readRaster(dem);
    ASSERT_EQ(relief.width, 32);
    ASSERT_EQ(relief.height, 32);
    ASSERT_EQ(relief.bands, 1);
    EXPECT_EQ(relief.type, GDT_Float32);
    for (int i = 0; i < 6; ++i) EXPECT_EQ(relief.transform[i], source.transform[i]) << i;
    EXPECT_TRUE(relief.crs.IsSame(&source.crs));
    // NaN is the float output's nodata value though the DEM has no voids.
    EXPECT_TRUE(relief.hasNodata);
    EXPECT_TRUE(std::isnan(relief.nodata));
    for (int y = 0; y < 32; ++y) {
      for (int x = 0; x < 32; ++x) {
        ASSERT_NEAR(relief.at(0, x, y), std::sin(e * kDeg), 1e-4) << x << " " << y;
      }
    }
  }
}

// A plane tilted 20 deg towards the west, sun from the west at 45 deg: the
// angle between the normal and the sun is 90 - 20 - 45 deg.
TEST(AalRelief, SlopedPlaneFacingTheSunIsTheCosine) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 32, 20), out = dir.path() / "relief.tif";
  const auto r = runTool("aal-relief",
                         quoted(dem) + " -o " + quoted(out) +
                             " --format float --sky 0 -q --sun-azimuth 270 "
                             "--sun-elevation 45",
                         cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.out, "");  // -q
  const Raster relief = readRaster(out);
  const double expected = std::cos((90 - 20 - 45) * kDeg);
  for (int y = 0; y < 32; ++y) {
    for (int x = 0; x < 32; ++x) ASSERT_NEAR(relief.at(0, x, y), expected, 1e-4) << x << " " << y;
  }
}

// The sky alone on open flat ground is the full sky: 1, 255 in bytes.
TEST(AalRelief, SkyOnlyOnFlatGroundIsTheFullSky) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 24, 0), out = dir.path() / "sky.tif";
  auto r = runTool("aal-relief", quoted(dem) + " -o " + quoted(out) + " --sky-only --format float",
                   cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster sky = readRaster(out);
  for (const double v : sky.samples[0]) ASSERT_NEAR(v, 1.0, 1e-3);
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(out) + " --sky-only", cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster bytes = readRaster(out);
  EXPECT_EQ(bytes.type, GDT_Byte);
  for (const double v : bytes.samples[0]) ASSERT_EQ(v, 255);
}

TEST(AalRelief, VoidsAreNodata) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 24, 10, 5, 7), out = dir.path() / "relief.tif";
  auto r = runTool("aal-relief", quoted(dem) + " -o " + quoted(out), cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  Raster relief = readRaster(out);
  ASSERT_TRUE(relief.hasNodata);
  EXPECT_EQ(relief.nodata, 0);
  for (int y = 0; y < 24; ++y) {
    for (int x = 0; x < 24; ++x) {
      if (x == 5 && y == 7) {
        EXPECT_EQ(relief.at(0, x, y), 0);
      } else {
        ASSERT_GE(relief.at(0, x, y), 1) << x << " " << y;
      }
    }
  }
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(out) + " --format float --cog",
              cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  relief = readRaster(out);
  ASSERT_TRUE(relief.hasNodata);
  EXPECT_TRUE(std::isnan(relief.nodata));
  EXPECT_TRUE(std::isnan(relief.at(0, 5, 7)));
  EXPECT_FALSE(std::isnan(relief.at(0, 6, 7)));
}

// Colour relief: the ramp's colour at the texel's height times the shading;
// voids transparent.
TEST(AalRelief, ColourReliefIsTheRampTimesTheShading) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 24, 0, 2, 3), out = dir.path() / "colour.tif",
                 grey = dir.path() / "grey.tif", ramp = dir.path() / "ramp.txt";
  std::ofstream(ramp) << "0 0 0 0\n100 200 100 50\n1000 255 255 255\nnv 0 0 0 0\n";
  const std::string common = " --sky 0 --sun-elevation 30";
  auto r = runTool("aal-relief",
                   quoted(dem) + " -o " + quoted(out) + " --color-relief " + quoted(ramp) + common,
                   cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster colour = readRaster(out);
  ASSERT_EQ(colour.bands, 4);  // RGB + alpha for the void
  const double shade = std::sin(30 * kDeg);
  EXPECT_NEAR(colour.at(0, 10, 10), 200 * shade, 0.6);
  EXPECT_NEAR(colour.at(1, 10, 10), 100 * shade, 0.6);
  EXPECT_NEAR(colour.at(2, 10, 10), 50 * shade, 0.6);
  EXPECT_EQ(colour.at(3, 10, 10), 255);
  EXPECT_EQ(colour.at(3, 2, 3), 0);
  // Water where asked: the flat DEM at 100 m under a 100 m water level is water.
  r = runTool(
      "aal-relief",
      quoted(dem) + " -o " + quoted(out) + " --palette hypsometric" + " --water-level 100" + common,
      cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster water = readRaster(out);
  EXPECT_NEAR(water.at(2, 10, 10), 190 * shade, 0.6);  // the water's blue
  EXPECT_GT(water.at(2, 10, 10), water.at(0, 10, 10));
}

TEST(AalRelief, ResolutionKeepsTheExtent) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 40, 5), out = dir.path() / "half.tif";
  auto r = runTool("aal-relief", quoted(dem) + " -o " + quoted(out) + " --resolution 20m",
                   cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  Raster half = readRaster(out);
  const Raster source = readRaster(dem);
  EXPECT_EQ(half.width, 20);
  EXPECT_EQ(half.height, 20);
  EXPECT_EQ(half.transform[0], source.transform[0]);
  EXPECT_EQ(half.transform[3], source.transform[3]);
  EXPECT_EQ(half.transform[1], 20);
  EXPECT_EQ(half.transform[5], -20);
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(out) + " --resolution 2x", cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(readRaster(out).width, 80);
}

TEST(AalRelief, MultidirectionalOnFlatGroundIsSinOfTheElevation) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 16, 0), out = dir.path() / "md.tif";
  const auto r = runTool("aal-relief",
                         quoted(dem) + " -o " + quoted(out) +
                             " --multidirectional --sun-elevation 30 --sky 0 "
                             "--format float",
                         cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster md = readRaster(out);
  for (const double v : md.samples[0]) ASSERT_NEAR(v, 0.5, 1e-4);
}

// A tiled bake's folder (DEMs beyond one image are baked so) gives the
// same relief as the single-file map of the same bake. A bumpy DEM, so that
// the apertures differ from texel to texel.
TEST(AalRelief, TiledApertureFolderGivesTheSameRelief) {
  TempDir dir;
  std::vector<float> z(48 * 48);
  for (size_t i = 0; i < z.size(); ++i) {
    z[i] = static_cast<float>(50 * std::sin(0.3 * double(i % 48)) * std::cos(0.2 * double(i / 48)));
  }
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500005;
  geo.originY = 4000005;
  geo.stepX = geo.stepY = kCell;
  const fs::path dem = dir.path() / "bumps.tif", folder = dir.path() / "tiles",
                 single = dir.path() / "single.exr";
  writeFloatGeoTiff(dem.string(), 48, 48, z.data(), geo);
  const std::string bake = " --azimuths 16 --max-distance 200 -q";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) + " --tile-size 16" + bake)
                .exitCode,
            0);
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(single) + bake).exitCode, 0);
  const fs::path a = dir.path() / "a.tif", b = dir.path() / "b.tif";
  for (const auto& [map, out] : {std::pair{folder, a}, std::pair{single, b}}) {
    const auto r = runTool("aal-relief", quoted(dem) + " --aperture " + quoted(map) + " -o " +
                                             quoted(out) + " --format float -q");
    ASSERT_EQ(r.exitCode, 0) << r.out;
  }
  const Raster ra = readRaster(a), rb = readRaster(b);
  EXPECT_EQ(ra.samples, rb.samples);
  double lo = 1, hi = 0;  // not a constant image
  for (const double v : ra.samples[0]) lo = std::min(lo, v), hi = std::max(hi, v);
  EXPECT_GT(hi - lo, 0.2);
}

// --time places the sun by the NOAA position at --lat/--lon: the same relief
// as that azimuth and elevation given by hand.
TEST(AalRelief, TimeGivesTheSolarPosition) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 16, 25), a = dir.path() / "a.tif", b = dir.path() / "b.tif";
  const std::string time = "2024-06-21T15:00:00Z";
  const SolarPosition sun = solarPosition(*parseIso8601Utc(time), 36.1, -84.2);
  char given[128];
  std::snprintf(given, sizeof given, " --sun-azimuth %.17g --sun-elevation %.17g", sun.azimuthDeg,
                sun.elevationDeg);
  const std::string common = " --format float -q --sky 0.3";
  auto r = runTool(
      "aal-relief",
      quoted(dem) + " -o " + quoted(a) + common + " --time " + time + " --lat 36.1 --lon -84.2",
      cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(b) + common + given, cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster ra = readRaster(a), rb = readRaster(b);
  EXPECT_EQ(ra.samples, rb.samples);
  // And not the default sun's relief: the time matters.
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(b) + common, cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(ra.samples, readRaster(b).samples);
}

// 8-bit output is gdaldem's 1 + 254 v; --stretch maps [LOW, HIGH] onto it.
TEST(AalRelief, ByteOutputAndStretch) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 16, 0), out = dir.path() / "b.tif";
  const std::string common = " --sky 0 --sun-elevation 30 -o " + quoted(out);
  auto r = runTool("aal-relief", quoted(dem) + common, cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster plain = readRaster(out);
  for (const double v : plain.samples[0]) ASSERT_EQ(v, 128);  // 1 + 254 * 0.5
  r = runTool("aal-relief", quoted(dem) + common + " --stretch 0.1,0.6", cacheEnv(dir));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Raster stretched = readRaster(out);
  for (const double v : stretched.samples[0]) ASSERT_EQ(v, 204);  // 1 + 254 * 0.8
}

// A write that fails half way (a file-size limit, as a full disk) exits 1,
// names the output and leaves nothing behind, as every tool's writes do.
TEST(AalRelief, AWriteThatFailsHalfWayExitsWithOneAndLeavesNothing) {
  TempDir inputs, outputs;
  const fs::path dem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";
  const fs::path map = inputs.path() / "a.exr", out = outputs.path() / "relief.tif";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --azimuths 8 -q").exitCode,
            0);
  const auto r =
      test::runShell("trap '' XFSZ; ulimit -f 16; " + quoted(test::binDir() / "aal-relief") + " " +
                     quoted(dem) + " --aperture " + quoted(map) + " -q -o " + quoted(out));
  EXPECT_EQ(r.exitCode, 1) << r.out;
  EXPECT_NE(r.out.find("cannot write"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("relief.tif"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find(".tmp-"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::is_empty(outputs.path()));
}

TEST(AalRelief, BadInputIsRefusedWithExitTwo) {
  TempDir dir;
  const fs::path dem = writePlane(dir, 16, 0), out = dir.path() / "r.tif",
                 ramp = dir.path() / "ramp.txt";
  std::ofstream(ramp) << "0 0 0 0\n100 1 2\n";
  struct Case {
    std::string arguments, message;
  };
  const std::vector<Case> cases = {
      {quoted(dem) + " -o " + quoted(dem), "is the input DEM"},
      {quoted(dem) + " -o " + quoted(out) + " --color-relief " + quoted(ramp), "ramp.txt:2:"},
      {quoted(dem) + " -o " + quoted(out) + " --sky-only --sun-azimuth 200", "--sky-only"},
      {quoted(dem) + " -o " + quoted(out) + " --sky-only --sky 0.5", "--sky-only"},
      {quoted(dem) + " -o " + quoted(out) + " --multidirectional --sun-azimuth 200",
       "--multidirectional"},
      {quoted(dem) + " -o " + quoted(out) + " --resolution fine", "--resolution"},
      {quoted(dem) + " -o " + quoted(out) + " --resolution 0.0001m", "pixels per side"},
      {quoted(dem) + " -o " + quoted(dir.path() / "r.png"), ".tif"},
      {quoted(dem) + " -o " + quoted(out) + " --palette rainbow", "unknown palette"},
      {quoted(dem) + " -o " + quoted(out) + " --palette earth --format float", "8-bit RGB"},
      {quoted(dem) + " -o " + quoted(out) + " --time yesterday", "ISO 8601"},
      {quoted(dem) + " -o " + quoted(out) + " --stretch 0.8,0.2", "--stretch"},
      {quoted(dem) + " -o " + quoted(out) + " --sun-elevation nan", "finite"},
      {quoted(dem) + " -o " + quoted(out) + " --water-mask " +
           quoted(writePlane(dir, 8, 0, -1, -1, "m.tif")),
       "DEM's size"},
      {quoted(dir.path() / "missing.tif") + " -o " + quoted(out), "missing.tif"},
  };
  for (const Case& c : cases) {
    const auto r = runTool("aal-relief", c.arguments, cacheEnv(dir));
    EXPECT_EQ(r.exitCode, 2) << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.arguments << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(out));
  const auto help = runTool("aal-relief", "--help");
  EXPECT_EQ(help.exitCode, 0);
  EXPECT_NE(help.out.find("--multidirectional"), std::string::npos);
}

}  // namespace
}  // namespace aal
