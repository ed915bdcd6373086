// The float32 GeoTIFF writer, checked by reading its files back with loadDem.
#include <gtest/gtest.h>

#include <filesystem>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/tests/terrain/io/dem_test_util.h"
#include "aperture/tests/terrain/io/gdal_raster.h"

namespace aal {
namespace {

std::vector<float> pattern(int width, int height) {
  std::vector<float> v(static_cast<size_t>(width * height));
  for (size_t i = 0; i < v.size(); ++i) v[i] = 0.001f * static_cast<float>(i * i) - 37.5f;
  return v;
}

class GeoTiffWriter : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

TEST_F(GeoTiffWriter, GeographicGridRoundTrips) {
  GeoReference geo;
  geo.crs = CrsKind::Geographic;
  geo.epsg = 4326;
  geo.originX = -84.41333333333333;
  geo.originY = 36.73250000000000;
  geo.stepX = geo.stepY = 1.0 / 1200.0;
  const std::vector<float> data = pattern(37, 21);  // more than one 16-row strip
  writeFloatGeoTiff(path("svf.tif"), 37, 21, data.data(), geo);
  const Heightfield f = loadDem(path("svf.tif"), warnings_.options());
  EXPECT_EQ(f.format, "GeoTIFF");
  EXPECT_EQ(f.z, data);
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  EXPECT_EQ(f.geo.epsg, 4326);
  EXPECT_NEAR(f.geo.originX, geo.originX, 1e-12);
  EXPECT_NEAR(f.geo.originY, geo.originY, 1e-12);
  EXPECT_NEAR(f.geo.stepX, geo.stepX, 1e-15);
  EXPECT_TRUE(warnings_.messages.empty()) << ::testing::PrintToString(warnings_.messages);
}

TEST_F(GeoTiffWriter, ProjectedGridsKeepCodeAndUnit) {
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 2229;  // California zone V, US survey feet
  geo.originX = 6500000.5;
  geo.originY = 1900000.25;
  geo.stepX = geo.stepY = 10.0;
  geo.linearUnitM = 1200.0 / 3937.0;
  const std::vector<float> data = pattern(5, 4);
  writeFloatGeoTiff(path("ft.tif"), 5, 4, data.data(), geo);
  Heightfield f = loadDem(path("ft.tif"), warnings_.options());
  EXPECT_EQ(f.geo.epsg, 2229);
  EXPECT_NEAR(f.geo.linearUnitM, 1200.0 / 3937.0, 1e-15);
  EXPECT_NEAR(f.cellSizeXM, 3.048006, 1e-6);
  EXPECT_NEAR(f.geo.originX, geo.originX, 1e-9);
  EXPECT_NEAR(f.geo.originY, geo.originY, 1e-9);

  geo.epsg = 0;  // user-defined CRS with an unusual unit
  geo.linearUnitM = 2.5;
  writeFloatGeoTiff(path("local.tif"), 5, 4, data.data(), geo);
  f = loadDem(path("local.tif"), warnings_.options());
  EXPECT_EQ(f.geo.epsg, 0);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 25.0);
  EXPECT_EQ(f.z, data);
}

TEST_F(GeoTiffWriter, NoGeoreferenceWritesAPlainTiff) {
  const std::vector<float> data = pattern(3, 2);
  writeFloatGeoTiff(path("plain.tif"), 3, 2, data.data(), GeoReference{});
  const Heightfield f = loadDem(path("plain.tif"), warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::None);
  EXPECT_EQ(f.z, data);
}

TEST_F(GeoTiffWriter, CarriesTheDemsCrsNodataAndWritesCogs) {
  // An ESRI-WKT CRS read from a DEM goes out as the same CRS.
  test::GdalRaster r;
  r.width = 1100;  // more than one 512-texel COG tile: overviews
  r.height = 700;
  r.hasTransform = true;
  const double t[6] = {1113194.9, 100, 0, 8399737.9, 0, -100};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:3857";
  ASSERT_TRUE(test::writeGdalRaster(path("dem.tif"), r));
  const Heightfield dem = loadDem(path("dem.tif"), warnings_.options());
  std::vector<float> data(dem.z.begin(), dem.z.end());
  data[5] = -9999.0f;
  RasterWriteOptions options;
  options.cog = true;
  options.nodata = -9999.0;
  writeFloatGeoTiff(path("svf.tif"), dem.width, dem.height, data.data(), dem.geo, options);

  GDALDatasetUniquePtr in(GDALDataset::Open(path("svf.tif").c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(in);
  const char* layout = in->GetMetadataItem("LAYOUT", "IMAGE_STRUCTURE");
  ASSERT_NE(layout, nullptr);
  EXPECT_STREQ(layout, "COG");
  double written[6];
  ASSERT_EQ(in->GetGeoTransform(written), CE_None);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(written[i], t[i], 1e-6) << i;
  OGRSpatialReference expected;
  expected.importFromEPSG(3857);
  ASSERT_NE(in->GetSpatialRef(), nullptr);
  EXPECT_TRUE(in->GetSpatialRef()->IsSame(&expected));
  int hasNodata = 0;
  EXPECT_EQ(in->GetRasterBand(1)->GetNoDataValue(&hasNodata), -9999.0);
  EXPECT_TRUE(hasNodata);
  EXPECT_GT(in->GetRasterBand(1)->GetOverviewCount(), 0);
  const Heightfield back = loadDem(path("svf.tif"), warnings_.options());
  EXPECT_EQ(back.voidCount, 1u);
  EXPECT_EQ(back.at(10, 10), dem.at(10, 10));
}

// Shaded-relief maps (aal-relief): 8-bit RGB + alpha, tagged so that GIS
// tools show colour and treat alpha 0 as transparent, samples per band.
TEST_F(GeoTiffWriter, WritesByteRgbaWithColourInterpretation) {
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500015;
  geo.originY = 4000015;
  geo.stepX = 30;
  geo.stepY = 20;
  const int w = 37, h = 5;
  std::vector<uint8_t> pixels(static_cast<size_t>(w) * h * 4);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>((i * 7) % 256);
  for (const bool cog : {false, true}) {
    RasterWriteOptions options;
    options.cog = cog;
    writeGeoTiff(path("rgba.tif"), RasterImage{w, h, 4, RasterSampleType::Byte, pixels.data()}, geo,
                 options);
    GDALDatasetUniquePtr in(GDALDataset::Open(path("rgba.tif").c_str(), GDAL_OF_RASTER));
    ASSERT_TRUE(in);
    ASSERT_EQ(in->GetRasterCount(), 4);
    const GDALColorInterp expected[] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
    for (int b = 1; b <= 4; ++b) {
      GDALRasterBand& band = *in->GetRasterBand(b);
      EXPECT_EQ(band.GetRasterDataType(), GDT_Byte);
      EXPECT_EQ(band.GetColorInterpretation(), expected[b - 1]) << b << " cog " << cog;
      std::vector<uint8_t> back(static_cast<size_t>(w) * h);
      ASSERT_EQ(band.RasterIO(GF_Read, 0, 0, w, h, back.data(), w, h, GDT_Byte, 0, 0, nullptr),
                CE_None);
      for (size_t i = 0; i < back.size(); ++i) {
        ASSERT_EQ(back[i], pixels[i * 4 + static_cast<size_t>(b - 1)]) << b << " " << i;
      }
    }
    double t[6];
    ASSERT_EQ(in->GetGeoTransform(t), CE_None);
    EXPECT_DOUBLE_EQ(t[0], 500000);
    EXPECT_DOUBLE_EQ(t[1], 30);
    EXPECT_DOUBLE_EQ(t[3], 4000025);
    EXPECT_DOUBLE_EQ(t[5], -20);
  }
  EXPECT_THROW(
      writeGeoTiff(path("b.tif"), RasterImage{w, h, 5, RasterSampleType::Byte, pixels.data()}, geo),
      std::invalid_argument);
}

TEST_F(GeoTiffWriter, ReplacesAnExistingFileAndLeavesNoTemporaryFile) {
  const std::vector<float> first = pattern(3, 2), second(6, 9.0f);
  writeFloatGeoTiff(path("out.tif"), 3, 2, first.data(), GeoReference{});
  writeFloatGeoTiff(path("out.tif"), 3, 2, second.data(), GeoReference{});
  EXPECT_EQ(loadDem(path("out.tif"), warnings_.options()).z, second);
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir_.path()))
    ++files;
  EXPECT_EQ(files, 1u);
}

TEST_F(GeoTiffWriter, MissingFolderFailsWithoutOutput) {
  const std::vector<float> data = pattern(3, 2);
  EXPECT_THROW(writeFloatGeoTiff(path("no/such/out.tif"), 3, 2, data.data(), GeoReference{}),
               std::runtime_error);
  EXPECT_FALSE(std::filesystem::exists(path("no")));
}

TEST_F(GeoTiffWriter, InvalidArgumentsThrow) {
  const std::vector<float> data = pattern(3, 2);
  EXPECT_THROW(writeFloatGeoTiff(path("a.tif"), 0, 2, data.data(), GeoReference{}),
               std::invalid_argument);
  EXPECT_THROW(writeFloatGeoTiff(path("a.tif"), 3, 2, nullptr, GeoReference{}),
               std::invalid_argument);
  GeoReference geo;
  geo.crs = CrsKind::Projected;  // steps left at 0
  EXPECT_THROW(writeFloatGeoTiff(path("a.tif"), 3, 2, data.data(), geo), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path("a.tif")));
}

}  // namespace
}  // namespace aal
