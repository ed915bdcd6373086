// The GIS conventions of every GeoTIFF the tools write (aal-bake --svf,
// --visible, -o map.tif; aal-relief), read back with GDAL as gdalinfo would:
// placed like the DEM, NaN nodata for floats, band descriptions, the TIFF
// Software tag, overviews with --overviews and with -of COG, -co given to
// GDAL, bad -co refused (exit 2) before any work. And the map as GeoTIFF
// renders as its EXR does (docs/baking.md).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <OpenImageIO/imageio.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/version.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

constexpr float kIntegerNodata = -32768;  // an SRTM-style nodata the outputs must not reuse

// Hills on a UTM grid of 10 m cells, `voids` texels of the DEM's -32768.
fs::path writeDem(const TempDir& dir, int width, int height, int voids) {
  std::vector<float> z(static_cast<size_t>(width) * height);
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      z[static_cast<size_t>(r) * width + c] =
          static_cast<float>(300 + 40 * std::sin(c * 0.07) * std::cos(r * 0.05));
    }
  }
  for (int i = 0; i < voids; ++i) z[static_cast<size_t>(20 + i) * width + 30] = kIntegerNodata;
  RasterWriteOptions options;
  options.nodata = kIntegerNodata;
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500005;
  geo.originY = 4000005;
  geo.stepX = geo.stepY = 10;
  const fs::path path = dir.path() / "dem.tif";
  writeFloatGeoTiff(path.string(), width, height, z.data(), geo, options);
  return path;
}

GDALDatasetUniquePtr open(const fs::path& path) {
  ensureGdal();
  return GDALDatasetUniquePtr(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER));
}

// What every output shares: the DEM's geotransform and CRS, the software.
void expectPlacedLikeTheDem(const fs::path& output, const fs::path& dem) {
  SCOPED_TRACE(output.filename().string());
  GDALDatasetUniquePtr out = open(output), in = open(dem);
  ASSERT_TRUE(out);
  ASSERT_TRUE(in);
  double have[6], want[6];
  ASSERT_EQ(out->GetGeoTransform(have), CE_None);
  ASSERT_EQ(in->GetGeoTransform(want), CE_None);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(have[i], want[i]) << i;
  ASSERT_NE(out->GetSpatialRef(), nullptr);
  EXPECT_TRUE(out->GetSpatialRef()->IsSame(in->GetSpatialRef()));
  const char* software = out->GetMetadataItem("TIFFTAG_SOFTWARE");
  ASSERT_NE(software, nullptr);
  EXPECT_NE(std::string(software).find(std::string("aperture ") + versionNumber()),
            std::string::npos)
      << software;
}

// A float band's nodata is NaN and its voids hold it.
void expectNanNodata(const fs::path& output, int voids) {
  SCOPED_TRACE(output.filename().string());
  GDALDatasetUniquePtr out = open(output);
  ASSERT_TRUE(out);
  GDALRasterBand& band = *out->GetRasterBand(1);
  int has = 0;
  EXPECT_TRUE(std::isnan(band.GetNoDataValue(&has)));
  EXPECT_TRUE(has);
  std::vector<float> v(static_cast<size_t>(band.GetXSize()) * band.GetYSize());
  ASSERT_EQ(band.RasterIO(GF_Read, 0, 0, band.GetXSize(), band.GetYSize(), v.data(),
                          band.GetXSize(), band.GetYSize(), GDT_Float32, 0, 0, nullptr),
            CE_None);
  EXPECT_EQ(std::count_if(v.begin(), v.end(), [](float x) { return std::isnan(x); }), voids);
  EXPECT_EQ(std::count(v.begin(), v.end(), kIntegerNodata), 0);
}

std::string compressionOf(const fs::path& output) {
  GDALDatasetUniquePtr out = open(output);
  const char* c = out ? out->GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE") : nullptr;
  return c ? c : "";
}

int overviewsOf(const fs::path& output) {
  GDALDatasetUniquePtr out = open(output);
  return out ? out->GetRasterBand(1)->GetOverviewCount() : -1;
}

std::string descriptionOf(const fs::path& output, int band) {
  GDALDatasetUniquePtr out = open(output);
  return out ? out->GetRasterBand(band)->GetDescription() : "";
}

TEST(GeoTiffOutputs, BakeOutputsFollowGdalConventions) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 300, 270, 6);
  const fs::path svf = dir.path() / "svf.tif", visible = dir.path() / "visible.tif",
                 map = dir.path() / "map.tif";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --svf " + quoted(svf) +
                                         " --visible " + quoted(visible) +
                                         " --azimuths 16 -q --overviews -co COMPRESS=LZW");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  for (const fs::path& output : {svf, visible, map}) {
    expectPlacedLikeTheDem(output, dem);
    EXPECT_EQ(compressionOf(output), "LZW") << output;
    EXPECT_EQ(overviewsOf(output), 1) << output;  // 300 -> 150
  }
  expectNanNodata(svf, 6);
  expectNanNodata(visible, 6);
  EXPECT_EQ(descriptionOf(svf, 1), "sky-view factor");
  EXPECT_EQ(descriptionOf(visible, 1), "visible sky fraction (solid angle / 2 pi)");
  EXPECT_EQ(descriptionOf(map, 1), "bent normal x (east)");
  EXPECT_EQ(descriptionOf(map, 4), "aperture arc length (rad)");
}

// Float rasters are deflated at level 1 (their mantissas' low bits are
// noise that higher levels do not squeeze) unless -co sets a level: the
// default writes the file -co ZLEVEL=1 writes, not the one level 6 does.
TEST(GeoTiffOutputs, FloatsAreDeflatedAtTheFastestLevelUnlessAsked) {
  TempDir dir;
  constexpr int kWidth = 300, kHeight = 270;
  std::vector<float> z(static_cast<size_t>(kWidth) * kHeight);
  for (size_t i = 0; i < z.size(); ++i) {
    z[i] = static_cast<float>(0.8 + 0.1 * std::sin(0.013 * i) + 1e-4 * std::sin(7.1 * i));
  }
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.stepX = geo.stepY = 10;
  const auto written = [&](const std::string& name, std::vector<std::string> creationOptions) {
    RasterWriteOptions options;
    options.creationOptions = std::move(creationOptions);
    const fs::path path = dir.path() / name;
    writeFloatGeoTiff(path.string(), kWidth, kHeight, z.data(), geo, options);
    return fs::file_size(path);
  };
  const uintmax_t byDefault = written("default.tif", {});
  EXPECT_EQ(byDefault, written("level1.tif", {"ZLEVEL=1"}));
  EXPECT_NE(byDefault, written("level6.tif", {"ZLEVEL=6"}));
  EXPECT_EQ(compressionOf(dir.path() / "default.tif"), "DEFLATE");
}

TEST(GeoTiffOutputs, CogOutputsHaveOverviews) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 600, 280, 0);
  const fs::path svf = dir.path() / "svf.tif", map = dir.path() / "map.exr";
  for (const std::string format : {"-of COG", "--cog", "-of cog"}) {
    SCOPED_TRACE(format);
    const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --svf " +
                                           quoted(svf) + " --azimuths 8 -q " + format);
    ASSERT_EQ(r.exitCode, 0) << r.out;
    GDALDatasetUniquePtr out = open(svf);
    ASSERT_TRUE(out);
    const char* layout = out->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
    EXPECT_STREQ(layout, "COG");
    EXPECT_GT(out->GetRasterBand(1)->GetOverviewCount(), 0);
    out.reset();
    expectPlacedLikeTheDem(svf, dem);
    expectNanNodata(svf, 0);  // NaN declared though the DEM has no voids
  }
}

TEST(GeoTiffOutputs, ReliefOutputsFollowGdalConventions) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 300, 270, 4);
  const std::string cache = "AAL_CACHE_DIR=" + quoted(dir.path() / "cache");
  const fs::path grey = dir.path() / "grey.tif", value = dir.path() / "float.tif",
                 colour = dir.path() / "colour.tif";
  auto r = runTool(
      "aal-relief",
      quoted(dem) + " -o " + quoted(value) + " --format float -q --overviews -co " + "COMPRESS=LZW",
      cache);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  expectPlacedLikeTheDem(value, dem);
  expectNanNodata(value, 4);
  EXPECT_EQ(compressionOf(value), "LZW");
  EXPECT_EQ(overviewsOf(value), 1);
  EXPECT_EQ(descriptionOf(value, 1), "shaded relief (0..1)");
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(grey) + " -q -of COG", cache);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  expectPlacedLikeTheDem(grey, dem);
  EXPECT_EQ(descriptionOf(grey, 1), "shaded relief (1 + 254 v, 0 = nodata)");
  r = runTool("aal-relief",
              quoted(dem) + " -o " + quoted(colour) + " -q --palette hypsometric " + "--overviews",
              cache);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  expectPlacedLikeTheDem(colour, dem);
  EXPECT_EQ(overviewsOf(colour), 1);
  EXPECT_EQ(descriptionOf(colour, 1), "shaded colour relief (red)");
}

TEST(GeoTiffOutputs, BadCreationOptionsAreRefusedBeforeAnyWork) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 40, 30, 0);
  const fs::path svf = dir.path() / "svf.tif", map = dir.path() / "map.exr";
  const std::string outputs = quoted(dem) + " -o " + quoted(map) + " --svf " + quoted(svf) + " -q ";
  auto r = runTool("aal-bake", outputs + "-co BOGUS");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("-co BOGUS: a creation option is KEY=VALUE"), std::string::npos) << r.out;
  r = runTool("aal-bake", outputs + "-co BOGUS=1");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("BOGUS"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("GTiff"), std::string::npos) << r.out;
  r = runTool("aal-bake", outputs + "-co COMPRESS=NOPE");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("NOPE"), std::string::npos) << r.out;
  r = runTool("aal-bake", outputs + "--cog -of GTiff");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  r = runTool("aal-relief", quoted(dem) + " -o " + quoted(svf) + " -q -co BOGUS");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("KEY=VALUE"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(svf));
  EXPECT_FALSE(fs::exists(map));
}

// A tiled bake's SVF tiles take -co and --overviews, hold NaN at the voids,
// and their VRT mosaic keeps the nodata and the band's description; -of
// COG, which the mosaic could not use, is refused before the bake.
TEST(GeoTiffOutputs, TiledSvfTilesTakeCreationOptionsAndTheMosaicTheirLabels) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 60, 50, 4);
  const fs::path folder = dir.path() / "tiles";
  const std::string bake = quoted(dem) + " -o " + quoted(folder) + " --tile-size 32 --svf " +
                           "--azimuths 8 --max-distance 200 -q ";
  auto r = runTool("aal-bake", bake + "-of COG");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("leave out -of COG"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(folder / "index.txt"));
  r = runTool("aal-bake", bake + "-co COMPRESS=LZW");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(compressionOf(folder / "svf_0001_0001.tif"), "LZW");
  EXPECT_EQ(descriptionOf(folder / "svf_0000_0000.tif", 1), "sky-view factor");
  const fs::path mosaic = folder / "sky_view_factor.vrt";
  EXPECT_EQ(descriptionOf(mosaic, 1), "sky-view factor");
  expectNanNodata(mosaic, 4);
  GDALDatasetUniquePtr in = open(mosaic), source = open(dem);
  ASSERT_TRUE(in);
  double have[6], want[6];
  ASSERT_EQ(in->GetGeoTransform(have), CE_None);
  ASSERT_EQ(source->GetGeoTransform(want), CE_None);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(have[i], want[i]) << i;
}

// What a GIS user sees first: gdalinfo -json -stats on the map and the SVF.
TEST(GeoTiffOutputs, GdalinfoJsonShowsBandsCrsNodataAndSoftware) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 64, 48, 3);
  const fs::path map = dir.path() / "map.tif", svf = dir.path() / "svf.tif";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --svf " + quoted(svf) +
                                         " --azimuths 8 -q");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const auto info = test::runShell("gdalinfo -json -stats " + quoted(map) + " 2>/dev/null");
  ASSERT_EQ(info.exitCode, 0) << info.out;
  for (const char* expected :
       {"\"band\":4,", "\"description\":\"bent normal x (east)\"",
        "\"description\":\"bent normal y (north)\"", "\"description\":\"bent normal z (up)\"",
        "\"description\":\"aperture arc length (rad)\"", "\"unit\":\"rad\"",
        "ID[\\\"EPSG\\\",32616]", "\"TIFFTAG_SOFTWARE\":\"aperture ", "\"AAL_SOURCE\":\"dem.tif\"",
        "\"mean\":"}) {
    EXPECT_NE(info.out.find(expected), std::string::npos) << expected << "\n" << info.out;
  }
  EXPECT_EQ(info.out.find("\"band\":5,"), std::string::npos);
  const auto svfInfo = test::runShell("gdalinfo -json -stats " + quoted(svf) + " 2>/dev/null");
  ASSERT_EQ(svfInfo.exitCode, 0) << svfInfo.out;
  EXPECT_NE(svfInfo.out.find("\"noDataValue\":\"NaN\""), std::string::npos) << svfInfo.out;
  EXPECT_NE(svfInfo.out.find("\"description\":\"sky-view factor\""), std::string::npos);
  EXPECT_EQ(svfInfo.out.find("-32768"), std::string::npos) << svfInfo.out;
}

std::vector<float> floatPixels(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<float> pixels(spec.image_pixels() * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data())) return {};
  return pixels;
}

// The renderer holds the map as halves: the GeoTIFF's floats round to the
// halves the EXR stores (the same rounding), so the images are the same.
TEST(GeoTiffOutputs, TheMapAsGeoTiffRendersAsItsExr) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 48, 40, 0);
  const fs::path exr = dir.path() / "map.exr", tif = dir.path() / "map.tif";
  for (const fs::path& map : {exr, tif}) {
    const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --azimuths 16 -q");
    ASSERT_EQ(r.exitCode, 0) << r.out;
  }
  std::vector<std::vector<float>> images;
  for (const fs::path& map : {exr, tif}) {
    const fs::path out = dir.path() / (map.stem().string() + map.extension().string() + ".exr");
    const auto r = runTool("aal-render", quoted(dem) + " --aperture " + quoted(map) + " -o " +
                                             quoted(out) + " --size 64x36");
    ASSERT_EQ(r.exitCode, 0) << r.out;
    images.push_back(floatPixels(out));
    ASSERT_FALSE(images.back().empty());
  }
  EXPECT_EQ(images[0], images[1]);

  // A truncated GeoTIFF: a clear refusal, exit 2.
  fs::resize_file(tif, fs::file_size(tif) / 2);
  const auto r = runTool("aal-render", quoted(dem) + " --aperture " + quoted(tif) + " -o " +
                                           quoted(dir.path() / "x.png") + " --size 64x36");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("truncated or corrupt"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("map.tif"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace aal
