// The sky-view factor of aal-bake's tiled bake (--svf without a path): a
// GeoTIFF per tile beside its EXR and their VRT mosaic, read back with GDAL
// against the whole-DEM bake's --svf GeoTIFF; resumed and refused like the
// tiles.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::folderContents;
using test::quoted;
using test::runTool;
using test::TempDir;

// A synthetic DEM as a float GeoTIFF, projected (UTM, 30 m) or geographic
// (1/1200 degree, whose steps are not binary fractions); `voids` texels
// set to the nodata value -9999.
fs::path writeDem(const TempDir& dir, const std::string& name, int width, int height,
                  bool geographic, int voids = 0) {
  SyntheticTerrainOptions s;
  s.width = width;
  s.height = height;
  s.cellSizeM = 30;
  s.seed = 5;
  s.featureSizeTexels = 20;
  Heightfield field = makeSyntheticTerrain(s);
  RasterWriteOptions options;
  if (voids > 0) {
    options.nodata = -9999.0;
    for (int i = 0; i < voids; ++i) field.z[static_cast<size_t>(i) * 97 % field.z.size()] = -9999;
  }
  const GeoReference geo = test::testGeoReference(geographic);
  const fs::path path = dir.path() / name;
  writeFloatGeoTiff(path.string(), width, height, field.z.data(), geo, options);
  return path;
}

struct Raster {
  int width = 0, height = 0;
  double transform[6] = {};
  OGRSpatialReference crs;
  bool hasNodata = false;
  double nodata = 0;
  std::vector<float> values;  // row-major
};

Raster readRaster(const fs::path& path) {
  ensureGdal();
  Raster r;
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) {
    ADD_FAILURE() << "GDAL cannot open " << path;
    return r;
  }
  r.width = ds->GetRasterXSize();
  r.height = ds->GetRasterYSize();
  EXPECT_EQ(ds->GetGeoTransform(r.transform), CE_None) << path;
  if (ds->GetSpatialRef()) r.crs = *ds->GetSpatialRef();
  int has = 0;
  r.nodata = ds->GetRasterBand(1)->GetNoDataValue(&has);
  r.hasNodata = has != 0;
  EXPECT_EQ(ds->GetRasterBand(1)->GetRasterDataType(), GDT_Float32) << path;
  r.values.resize(static_cast<size_t>(r.width) * r.height);
  EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, r.width, r.height, r.values.data(),
                                           r.width, r.height, GDT_Float32, 0, 0, nullptr),
            CE_None);
  return r;
}

// Bit for bit, NaN (nodata) included.
bool sameBits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

// The folder's files but its lock, which the bakes leave empty.
test::FolderContents bakeFiles(const fs::path& folder) {
  test::FolderContents files = folderContents(folder);
  files.erase(".aal-bake.lock");
  return files;
}

// With --max-distance the tiles are the whole-DEM bake's texels, so the SVF
// mosaic read through the VRT is the whole-DEM --svf GeoTIFF bit for bit,
// placed exactly like the DEM (geotransform, CRS, nodata and its voids), on
// a projected grid with voids and on a geographic one (20 tiles of a step of
// 1/1200 degree, whose mean over the tiles, GDALBuildVRT's default
// resolution, is not the step); each tile is placed
// like its window; the folder moved elsewhere still reads (relative paths).
TEST(AalBakeTiledSvf, MosaicEqualsTheWholeDemSvfWithMaxDistance) {
  TempDir dir;
  for (const bool geographic : {false, true}) {
    SCOPED_TRACE(geographic ? "geographic" : "projected with voids");
    const fs::path dem =
        writeDem(dir, geographic ? "geo.tif" : "utm.tif", 90, 70, geographic, geographic ? 0 : 5);
    const std::string options = " --azimuths 16 --max-distance 250 -q";
    const fs::path single = dir.path() / "single.exr", svf = dir.path() / "svf.tif",
                   folder = dir.path() / "tiles";
    fs::remove_all(folder);
    auto r = runTool("aal-bake",
                     quoted(dem) + " -o " + quoted(single) + " --svf " + quoted(svf) + options);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    r = runTool("aal-bake",
                quoted(dem) + " -o " + quoted(folder) + " --tile-size 20 --svf" + options);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    for (int row = 0; row < 4; ++row) {
      for (int column = 0; column < 5; ++column) {
        char name[32];
        std::snprintf(name, sizeof name, "svf_%04d_%04d.tif", row, column);
        EXPECT_TRUE(fs::exists(folder / name)) << name;
      }
    }
    const Raster want = readRaster(svf), demRaster = readRaster(dem);
    const Raster have = readRaster(folder / "sky_view_factor.vrt");
    ASSERT_EQ(have.width, 90);
    ASSERT_EQ(have.height, 70);
    for (int i = 0; i < 6; ++i) {
      EXPECT_EQ(have.transform[i], demRaster.transform[i]) << i;
      EXPECT_EQ(want.transform[i], demRaster.transform[i]) << i;
    }
    EXPECT_TRUE(have.crs.IsSame(&demRaster.crs));
    // NaN, the float nodata value, in the mosaic and the whole-DEM file
    // alike, with or without voids; never the DEM's -9999.
    EXPECT_TRUE(have.hasNodata);
    EXPECT_TRUE(want.hasNodata);
    EXPECT_TRUE(std::isnan(have.nodata));
    EXPECT_TRUE(std::isnan(want.nodata));
    EXPECT_TRUE(sameBits(have.values, want.values));
    EXPECT_EQ(std::count_if(have.values.begin(), have.values.end(),
                            [](float v) { return std::isnan(v); }),
              geographic ? 0 : 5);
    EXPECT_EQ(std::count(have.values.begin(), have.values.end(), -9999.0f), 0);
    // Terrain hides some sky: the values are not all one.
    EXPECT_GT(std::count_if(want.values.begin(), want.values.end(),
                            [](float v) { return v > 0.0f && v < 0.99f; }),
              100);

    // Tile (3, 4) is the DEM's window from column 80, row 60.
    const Raster tile = readRaster(folder / "svf_0003_0004.tif");
    EXPECT_EQ(tile.width, 10);
    EXPECT_EQ(tile.height, 10);
    EXPECT_DOUBLE_EQ(tile.transform[0], demRaster.transform[0] + 80 * demRaster.transform[1]);
    EXPECT_DOUBLE_EQ(tile.transform[3], demRaster.transform[3] + 60 * demRaster.transform[5]);
    EXPECT_EQ(tile.transform[1], demRaster.transform[1]);
    EXPECT_EQ(tile.transform[5], demRaster.transform[5]);
    EXPECT_TRUE(tile.crs.IsSame(&demRaster.crs));

    const fs::path moved = dir.path() / "moved";
    fs::remove_all(moved);
    fs::rename(folder, moved);
    EXPECT_TRUE(sameBits(readRaster(moved / "sky_view_factor.vrt").values, want.values));
    fs::remove_all(moved);
  }
}

// Without --max-distance the far field completes the horizons: the mosaic
// is close to the whole-DEM SVF, within the bounds the far field's aperture
// tests hold the visible fraction to (far_field_test.cpp: mean 0.002, 99th
// percentile 0.01). The DEM read in bands (--low-memory) writes the same
// folder, byte for byte: the GeoTIFFs and the VRT carry no date.
TEST(AalBakeTiledSvf, FarFieldMosaicIsCloseToTheWholeDemSvf) {
  TempDir dir;
  const fs::path dem = writeDem(dir, "dem.tif", 150, 120, false);
  const fs::path single = dir.path() / "a.exr", svf = dir.path() / "svf.tif",
                 memory = dir.path() / "memory", bands = dir.path() / "bands";
  const std::string fixedDate = "SOURCE_DATE_EPOCH=1700000000";
  auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(single) + " --svf " + quoted(svf) +
                                   " --azimuths 16 -q");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  // A near reach of 32 cells: the default's 128 and two blocks would walk
  // every line across the whole 150 columns, leaving nothing to the far field.
  const std::string tiled = " --tile-size 16 --near-reach 960 --svf --azimuths 16 -q";
  r = runTool("aal-bake", quoted(dem) + " -o " + quoted(memory) + tiled, fixedDate);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  r = runTool("aal-bake", quoted(dem) + " -o " + quoted(bands) + tiled + " --low-memory",
              fixedDate);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_TRUE(bakeFiles(memory) == bakeFiles(bands));
  EXPECT_EQ(bakeFiles(memory).size(), 80u + 80u + 3u);  // EXRs, GeoTIFFs, VRT, index, manifest

  const Raster want = readRaster(svf), have = readRaster(memory / "sky_view_factor.vrt");
  ASSERT_EQ(have.values.size(), want.values.size());
  std::vector<double> error(want.values.size());
  for (size_t i = 0; i < error.size(); ++i) {
    error[i] = std::abs(static_cast<double>(have.values[i]) - want.values[i]);
  }
  double mean = 0.0;
  for (const double e : error) mean += e;
  mean /= static_cast<double>(error.size());
  std::sort(error.begin(), error.end());
  const double p99 = error[error.size() * 99 / 100], largest = error.back();
  std::printf("far-field SVF against the whole-DEM bake: mean |d| %.3g, p99 %.3g, max %.3g\n", mean,
              p99, largest);
  EXPECT_LE(mean, 0.002);
  EXPECT_LE(p99, 0.01);
  EXPECT_GT(largest, 0.0);  // the far field is not the whole DEM: the comparison can fail
}

// A tile counts as finished only with its SVF GeoTIFF: one removed, or cut
// short so that GDAL cannot read it, is baked again, to the same bytes.
// Whether a folder holds the SVF is part of its bake: a folder baked with it
// is refused to a bake without it and the other way round, untouched.
TEST(AalBakeTiledSvf, ResumeBakesTilesWithoutTheirSvfAndTheSvfIsPartOfTheBake) {
  TempDir dir;
  const fs::path dem = writeDem(dir, "dem.tif", 90, 70, false);
  const fs::path folder = dir.path() / "t";
  const std::string fixedDate = "SOURCE_DATE_EPOCH=1700000000";
  const std::string base =
      quoted(dem) + " -o " + quoted(folder) + " --tile-size 32 --azimuths 16 --max-distance 200";
  auto r = runTool("aal-bake", base + " --svf", fixedDate);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const test::FolderContents whole = bakeFiles(folder);
  EXPECT_NE(whole.at("index.txt").find("sky-view-factor 1"), std::string::npos);

  fs::remove(folder / "index.txt");
  fs::remove(folder / "sky_view_factor.vrt");
  fs::remove(folder / "svf_0001_0001.tif");
  fs::resize_file(folder / "svf_0002_0000.tif", 100);
  r = runTool("aal-bake", base + " --svf", fixedDate);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("(2 baked, 7 resumed)"), std::string::npos) << r.out;
  EXPECT_TRUE(bakeFiles(folder) == whole);

  r = runTool("aal-bake", base, fixedDate);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("with the sky-view factor (--svf)"), std::string::npos) << r.out;
  EXPECT_TRUE(bakeFiles(folder) == whole);

  const fs::path plain = dir.path() / "plain";
  const std::string plainBase =
      quoted(dem) + " -o " + quoted(plain) + " --tile-size 32 --azimuths 16 --max-distance 200";
  ASSERT_EQ(runTool("aal-bake", plainBase + " -q").exitCode, 0);
  const test::FolderContents before = bakeFiles(plain);
  EXPECT_NE(before.at("index.txt").find("sky-view-factor 0"), std::string::npos);
  r = runTool("aal-bake", plainBase + " --svf");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("without the sky-view factor (--svf)"), std::string::npos) << r.out;
  EXPECT_TRUE(bakeFiles(plain) == before);
}

// Each SVF tile carries its place, its bake and the checksum of its pixels
// (GDAL metadata items). A tile's file swapped with its neighbour's (same
// size: only the items tell them apart) is refused naming it, exit 2, as an
// aperture tile of another place is, in a finished folder and in one whose
// bake was cut short, and the mosaic is not written over it; a tile whose
// pixels were changed behind its items is baked again. Put back, the folder
// resumes to the clean bake's bytes, and so does its mosaic.
TEST(AalBakeTiledSvf, SwappedOrAlteredSvfTilesAreCaughtAndNeverMosaicked) {
  TempDir dir;
  const fs::path dem = writeDem(dir, "dem.tif", 90, 70, false);
  const fs::path folder = dir.path() / "t";
  const std::string fixedDate = "SOURCE_DATE_EPOCH=1700000000";
  const std::string bake = quoted(dem) + " -o " + quoted(folder) +
                           " --tile-size 32 --azimuths 16 --max-distance 200 --svf";
  auto r = runTool("aal-bake", bake, fixedDate);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const test::FolderContents clean = bakeFiles(folder);
  const Raster cleanMosaic = readRaster(folder / "sky_view_factor.vrt");
  {
    GDALDatasetUniquePtr tile(GDALDataset::Open((folder / "svf_0001_0002.tif").c_str(),
                                                GDAL_OF_RASTER | GDAL_OF_READONLY));
    ASSERT_TRUE(tile);
    EXPECT_STREQ(tile->GetMetadataItem("AAL_TILE"), "1 2");
    EXPECT_STREQ(tile->GetMetadataItem("AAL_TILE_ORIGIN"), "64,32");
    EXPECT_STREQ(tile->GetMetadataItem("AAL_SOURCE_SIZE"), "90x70");
    ASSERT_NE(tile->GetMetadataItem("AAL_PIXEL_CHECKSUM"), nullptr);
    EXPECT_EQ(std::strlen(tile->GetMetadataItem("AAL_PIXEL_CHECKSUM")), 16u);
  }

  const fs::path a = folder / "svf_0000_0000.tif", b = folder / "svf_0000_0001.tif";
  const auto swapTiles = [&] {
    fs::rename(a, folder / "swap.tif");
    fs::rename(b, a);
    fs::rename(folder / "swap.tif", b);
  };
  swapTiles();
  const test::FolderContents swapped = bakeFiles(folder);
  r = runTool("aal-bake", bake, fixedDate);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(
      r.out.find("svf_0000_0000.tif does not belong to this tiled bake: its place in the DEM"),
      std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("remove the folder or write to another one"), std::string::npos) << r.out;
  EXPECT_TRUE(bakeFiles(folder) == swapped);

  // Cut short: no index, no mosaic. Still refused, and no mosaic of the
  // swapped tiles is written.
  fs::remove(folder / "index.txt");
  fs::remove(folder / "sky_view_factor.vrt");
  const test::FolderContents partial = bakeFiles(folder);
  r = runTool("aal-bake", bake, fixedDate);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("svf_0000_0000.tif does not belong to this tiled bake"), std::string::npos)
      << r.out;
  EXPECT_TRUE(bakeFiles(folder) == partial);
  EXPECT_FALSE(fs::exists(folder / "sky_view_factor.vrt"));

  // Put back, with other pixels under one tile's items: that tile is
  // baked again, the others resumed.
  swapTiles();
  {
    GDALDatasetUniquePtr tile(
        GDALDataset::Open((folder / "svf_0001_0001.tif").c_str(), GDAL_OF_RASTER | GDAL_OF_UPDATE));
    ASSERT_TRUE(tile);
    std::vector<float> values(32 * 32);
    ASSERT_EQ(tile->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 32, 32, values.data(), 32, 32,
                                               GDT_Float32, 0, 0, nullptr),
              CE_None);
    values[5 * 32 + 7] = values[5 * 32 + 7] > 0.5f ? 0.25f : 0.75f;
    ASSERT_EQ(tile->GetRasterBand(1)->RasterIO(GF_Write, 0, 0, 32, 32, values.data(), 32, 32,
                                               GDT_Float32, 0, 0, nullptr),
              CE_None);
  }
  ASSERT_FALSE(bakeFiles(folder).at("svf_0001_0001.tif") == clean.at("svf_0001_0001.tif"));
  r = runTool("aal-bake", bake, fixedDate);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("(1 baked, 8 resumed)"), std::string::npos) << r.out;
  EXPECT_TRUE(bakeFiles(folder) == clean)
      << ::testing::PrintToString(test::changedFiles(clean, bakeFiles(folder)));
  EXPECT_TRUE(sameBits(readRaster(folder / "sky_view_factor.vrt").values, cleanMosaic.values));
}

// --svf takes a path for a bake into one file and none for a tiled bake,
// whose DEM must be georeferenced to place the tiles; each misuse is said
// before any work and leaves no folder.
TEST(AalBakeTiledSvf, SvfPathsAndUnplacedDemsAreRefused) {
  TempDir dir;
  const fs::path dem = writeDem(dir, "dem.tif", 40, 40, false);
  std::vector<float> z(40 * 40, 100.0f);
  const fs::path local = dir.path() / "local.tif";
  writeFloatGeoTiff(local.string(), 40, 40, z.data(), GeoReference{});
  const fs::path folder = dir.path() / "t", file = dir.path() / "a.exr";
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {
           Case{quoted(dem) + " -o " + quoted(folder) + " --tile-size 16 --svf " +
                    quoted(dir.path() / "s.tif"),
                "give --svf without a path"},
           Case{quoted(dem) + " -o " + quoted(file) + " --svf", "--svf needs a path"},
           Case{quoted(local) + " --cell-size 30 -o " + quoted(folder) +
                    " --tile-size 16 --max-distance 100 --svf",
                "georeferencing"},
       }) {
    const auto r = runTool("aal-bake", c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(folder));
  EXPECT_FALSE(fs::exists(file));
}

}  // namespace
}  // namespace aal
