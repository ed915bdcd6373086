// RasterWriteOptions of the GeoTIFF writer, read back with GDAL: creation
// options over our defaults, and refused with GDAL's words; averaged
// overviews against a brute-force average; band descriptions, units and the
// TIFF Software tag.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gdal_priv.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/version.h"
#include "aperture/tests/terrain/io/dem_test_util.h"

namespace aal {
namespace {

GeoReference utm() {
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500005;
  geo.originY = 4000005;
  geo.stepX = geo.stepY = 10;
  return geo;
}

std::vector<float> ramp(int width, int height) {
  std::vector<float> v(static_cast<size_t>(width) * height);
  for (size_t i = 0; i < v.size(); ++i) v[i] = static_cast<float>((i * 37) % 101) * 0.25f;
  return v;
}

class GeoTiffWriteOptions : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  GDALDatasetUniquePtr open(const std::string& name) const {
    ensureGdal();
    return GDALDatasetUniquePtr(GDALDataset::Open(path(name).c_str(), GDAL_OF_RASTER));
  }
  test::TempDir dir_;
};

std::string compressionOf(GDALDataset& dataset) {
  const char* c = dataset.GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE");
  return c ? c : "";
}

TEST_F(GeoTiffWriteOptions, CreationOptionsOverrideOurDefaults) {
  const std::vector<float> data = ramp(40, 30);
  writeFloatGeoTiff(path("default.tif"), 40, 30, data.data(), utm());
  EXPECT_EQ(compressionOf(*open("default.tif")), "DEFLATE");
  RasterWriteOptions options;
  options.creationOptions = {"COMPRESS=LZW", "TILED=NO"};
  writeFloatGeoTiff(path("lzw.tif"), 40, 30, data.data(), utm(), options);
  GDALDatasetUniquePtr lzw = open("lzw.tif");
  ASSERT_TRUE(lzw);
  EXPECT_EQ(compressionOf(*lzw), "LZW");
  int blockWidth = 0, blockHeight = 0;
  lzw->GetRasterBand(1)->GetBlockSize(&blockWidth, &blockHeight);
  EXPECT_EQ(blockWidth, 40);  // strips, not our 256-texel tiles
  std::vector<float> back(data.size());
  ASSERT_EQ(lzw->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 40, 30, back.data(), 40, 30, GDT_Float32,
                                            0, 0, nullptr),
            CE_None);
  EXPECT_EQ(back, data);
  options.cog = true;
  options.creationOptions = {"COMPRESS=LZW"};
  writeFloatGeoTiff(path("cog.tif"), 40, 30, data.data(), utm(), options);
  EXPECT_EQ(compressionOf(*open("cog.tif")), "LZW");
}

// The message of checkCreationOptions' InputError, or "" when it passes.
std::string refusal(std::vector<std::string> creation, bool cog = false) {
  RasterWriteOptions options;
  options.cog = cog;
  options.creationOptions = std::move(creation);
  try {
    checkCreationOptions(options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(GeoTiffWriteOptions, RefusedCreationOptionsSayWhy) {
  EXPECT_EQ(refusal({"COMPRESS=LZW", "PREDICTOR=2", "BLOCKXSIZE=128"}), "");
  EXPECT_EQ(refusal({"BLOCKSIZE=256"}, /*cog=*/true), "");
  const std::string noValue = refusal({"BOGUS"});
  EXPECT_NE(noValue.find("-co BOGUS"), std::string::npos) << noValue;
  EXPECT_NE(noValue.find("KEY=VALUE"), std::string::npos) << noValue;
  EXPECT_NE(refusal({"=LZW"}).find("KEY=VALUE"), std::string::npos);
  const std::string unknown = refusal({"BOGUS=1"});
  EXPECT_NE(unknown.find("BOGUS"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("GTiff"), std::string::npos) << unknown;
  const std::string badValue = refusal({"COMPRESS=NOPE"});
  EXPECT_NE(badValue.find("NOPE"), std::string::npos) << badValue;
  // TILED is the GTiff driver's; a COG is always tiled and knows no TILED.
  const std::string cogTiled = refusal({"TILED=YES"}, /*cog=*/true);
  EXPECT_NE(cogTiled.find("TILED"), std::string::npos) << cogTiled;
  EXPECT_NE(cogTiled.find("COG"), std::string::npos) << cogTiled;
}

// The mean of the non-NaN texels of the 2x2 block at (x, y) of the level
// below: what GDAL's AVERAGE gives when NaN is the nodata value.
float blockMean(const std::vector<float>& level, int width, int x, int y) {
  double sum = 0;
  int count = 0;
  for (int dy = 0; dy < 2; ++dy) {
    for (int dx = 0; dx < 2; ++dx) {
      const float v = level[static_cast<size_t>(2 * y + dy) * width + (2 * x + dx)];
      if (std::isnan(v)) continue;
      sum += v;
      ++count;
    }
  }
  return count ? static_cast<float>(sum / count) : std::numeric_limits<float>::quiet_NaN();
}

TEST_F(GeoTiffWriteOptions, OverviewsAreAveragesDownToOneTile) {
  const int width = 600, height = 300;
  std::vector<float> data = ramp(width, height);
  data[0] = std::numeric_limits<float>::quiet_NaN();  // a void in the first block
  for (int i = 0; i < 4; ++i)
    data[static_cast<size_t>(2 * width + 2 + (i % 2)) + (i / 2) * width] =
        std::numeric_limits<float>::quiet_NaN();  // a block all void
  RasterWriteOptions options;
  options.nodata = std::numeric_limits<double>::quiet_NaN();
  writeFloatGeoTiff(path("plain.tif"), width, height, data.data(), utm(), options);
  EXPECT_EQ(open("plain.tif")->GetRasterBand(1)->GetOverviewCount(), 0);
  options.overviews = true;
  writeFloatGeoTiff(path("ovr.tif"), width, height, data.data(), utm(), options);
  GDALDatasetUniquePtr in = open("ovr.tif");
  GDALRasterBand& band = *in->GetRasterBand(1);
  // 600 -> 300 -> 150: halvings while the last is wider than a 256 tile.
  ASSERT_EQ(band.GetOverviewCount(), 2);
  GDALRasterBand& half = *band.GetOverview(0);
  ASSERT_EQ(half.GetXSize(), 300);
  ASSERT_EQ(half.GetYSize(), 150);
  EXPECT_EQ(band.GetOverview(1)->GetXSize(), 150);
  std::vector<float> back(300 * 150);
  ASSERT_EQ(
      half.RasterIO(GF_Read, 0, 0, 300, 150, back.data(), 300, 150, GDT_Float32, 0, 0, nullptr),
      CE_None);
  for (int y = 0; y < 150; ++y) {
    for (int x = 0; x < 300; ++x) {
      const float want = blockMean(data, width, x, y),
                  have = back[static_cast<size_t>(y) * 300 + x];
      if (std::isnan(want)) {
        ASSERT_TRUE(std::isnan(have)) << x << " " << y;
      } else {
        ASSERT_NEAR(have, want, 1e-5f * (1 + std::abs(want))) << x << " " << y;
      }
    }
  }
  EXPECT_TRUE(std::isnan(back[1 * 300 + 1]));  // the block all void
  // A COG has them without asking.
  options.overviews = false;
  options.cog = true;
  writeFloatGeoTiff(path("cog.tif"), width, height, data.data(), utm(), options);
  EXPECT_GT(open("cog.tif")->GetRasterBand(1)->GetOverviewCount(), 0);
}

TEST_F(GeoTiffWriteOptions, BandsCarryDescriptionsUnitsAndTheSoftware) {
  const int width = 9, height = 7;
  const std::vector<float> data = ramp(4 * width, height);
  for (const bool cog : {false, true}) {
    SCOPED_TRACE(cog ? "COG" : "GTiff");
    RasterWriteOptions options;
    options.cog = cog;
    options.bandLabels = {{"one", ""}, {"two", ""}, {"three", "m"}, {"four", "rad"}};
    writeGeoTiff(path("bands.tif"),
                 RasterImage{width, height, 4, RasterSampleType::Float32, data.data()}, utm(),
                 options);
    GDALDatasetUniquePtr in = open("bands.tif");
    ASSERT_TRUE(in);
    ASSERT_EQ(in->GetRasterCount(), 4);
    const char* names[] = {"one", "two", "three", "four"};
    const char* units[] = {"", "", "m", "rad"};
    for (int b = 1; b <= 4; ++b) {
      GDALRasterBand& band = *in->GetRasterBand(b);
      EXPECT_STREQ(band.GetDescription(), names[b - 1]);
      EXPECT_STREQ(band.GetUnitType(), units[b - 1]);
      // Float bands are values, not colours.
      EXPECT_NE(band.GetColorInterpretation(), GCI_RedBand);
      EXPECT_NE(band.GetColorInterpretation(), GCI_AlphaBand);
    }
    const char* software = in->GetMetadataItem("TIFFTAG_SOFTWARE");
    ASSERT_NE(software, nullptr);
    EXPECT_EQ(std::string(software), softwareName());
    EXPECT_NE(std::string(software).find(std::string("aperture ") + versionNumber()),
              std::string::npos);
  }
}

}  // namespace
}  // namespace aal
