// The aperture map as GeoTIFF (terrain/io/aperture_geotiff.h): written and
// read back bit for bit in float32 with its header; read as halves exactly
// as floatsToHalves rounds; placed and labelled for GIS tools; truncated,
// corrupt and foreign files refused with InputError.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <gdal_priv.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/aperture_geotiff.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/half_floats.h"
#include "aperture/terrain/version.h"
#include "aperture/tests/terrain/io/dem_test_util.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

ApertureMap sampleMap(int width, int height) {
  ApertureMap map;
  map.width = width;
  map.height = height;
  std::mt19937 random(7);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  map.texels.resize(map.texelCount() * 4);
  for (float& v : map.texels) v = unit(random);
  map.texels[5] = 1e-40f;  // a denormal survives too
  ApertureMapInfo& i = map.info;
  i.azimuths = 48;
  i.method = "sweep";
  i.cellSizeX = 10.25;
  i.cellSizeY = 9.75;
  i.zScale = 1.5;
  i.source = "dem.tif";
  i.sourceWidth = width;
  i.sourceHeight = height;
  i.sourceChecksum = "v2:0123456789abcdef";
  i.edge = "clamp";
  i.curvature = true;
  i.refraction = 0.13;
  i.maxDistanceM = 2500;
  return map;
}

GeoReference utm() {
  GeoReference geo;
  geo.crs = CrsKind::Projected;
  geo.epsg = 32616;
  geo.originX = 500005;
  geo.originY = 4000005;
  geo.stepX = geo.stepY = 10;
  return geo;
}

class ApertureGeoTiffTest : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  test::TempDir dir_;
};

TEST_F(ApertureGeoTiffTest, RoundTripsBitForBitWithItsHeader) {
  const ApertureMap map = sampleMap(37, 300);  // more than one block of rows
  writeApertureGeoTiff(path("map.tif"), map, utm());
  const ApertureMap back = readApertureMap(path("map.tif"));
  ASSERT_EQ(back.width, 37);
  ASSERT_EQ(back.height, 300);
  ASSERT_EQ(back.texels.size(), map.texels.size());
  EXPECT_EQ(std::memcmp(back.texels.data(), map.texels.data(), map.texels.size() * sizeof(float)),
            0);
  const ApertureMapInfo &want = map.info, &have = back.info;
  EXPECT_EQ(have.version, want.version);
  EXPECT_EQ(have.azimuths, want.azimuths);
  EXPECT_EQ(have.method, want.method);
  EXPECT_EQ(have.cellSizeX, want.cellSizeX);
  EXPECT_EQ(have.cellSizeY, want.cellSizeY);
  EXPECT_EQ(have.zScale, want.zScale);
  EXPECT_EQ(have.source, want.source);
  EXPECT_EQ(have.sourceWidth, want.sourceWidth);
  EXPECT_EQ(have.sourceHeight, want.sourceHeight);
  EXPECT_EQ(have.sourceChecksum, want.sourceChecksum);
  EXPECT_EQ(have.edge, want.edge);
  EXPECT_EQ(have.curvature, want.curvature);
  EXPECT_EQ(have.refraction, want.refraction);
  EXPECT_EQ(have.maxDistanceM, want.maxDistanceM);
  EXPECT_EQ(have.software, softwareName());
  EXPECT_EQ(have.originCol, 0);
}

// The renderer's rows: halves, rounded as the EXR writer rounds them.
TEST_F(ApertureGeoTiffTest, ReadsAsTheHalvesOfItsFloats) {
  const ApertureMap map = sampleMap(20, 11);
  writeApertureGeoTiff(path("map.tif"), map, utm());
  ApertureMapReader reader(path("map.tif"));
  EXPECT_EQ(reader.header().width, 20);
  ASSERT_TRUE(reader.header().pixelChecksum.has_value());
  std::vector<uint16_t> want(map.texels.size()), have(map.texels.size());
  floatsToHalves(map.texels.data(), want.data(), want.size());
  reader.readHalfRows(0, 4, have.data());
  reader.readHalfRows(4, 11, have.data() + 4 * 20 * 4);
  EXPECT_EQ(have, want);
}

TEST_F(ApertureGeoTiffTest, IsPlacedAndLabelledForGisTools) {
  writeApertureGeoTiff(path("map.tif"), sampleMap(12, 8), utm());
  ensureGdal();
  GDALDatasetUniquePtr in(GDALDataset::Open(path("map.tif").c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(in);
  ASSERT_EQ(in->GetRasterCount(), 4);
  const char* names[] = {"bent normal x (east)", "bent normal y (north)", "bent normal z (up)",
                         "aperture arc length (rad)"};
  for (int b = 1; b <= 4; ++b) {
    EXPECT_STREQ(in->GetRasterBand(b)->GetDescription(), names[b - 1]);
    EXPECT_EQ(in->GetRasterBand(b)->GetRasterDataType(), GDT_Float32);
  }
  EXPECT_STREQ(in->GetRasterBand(4)->GetUnitType(), "rad");
  double t[6];
  ASSERT_EQ(in->GetGeoTransform(t), CE_None);
  EXPECT_EQ(t[0], 500000);
  EXPECT_EQ(t[3], 4000010);
  EXPECT_EQ(t[1], 10);
  ASSERT_NE(in->GetSpatialRef(), nullptr);
  EXPECT_STREQ(in->GetSpatialRef()->GetAuthorityCode(nullptr), "32616");
  EXPECT_STREQ(in->GetMetadataItem("AAL_METHOD"), "sweep");
}

std::string inputErrorOf(const std::string& file) {
  try {
    readApertureMap(file);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST_F(ApertureGeoTiffTest, TruncatedCorruptAndForeignFilesAreInputErrors) {
  RasterWriteOptions raw;
  // Strips without padding: a changed byte in the middle is a changed value.
  raw.creationOptions = {"COMPRESS=NONE", "TILED=NO"};
  writeApertureGeoTiff(path("map.tif"), sampleMap(64, 64), utm(), raw);
  const auto size = fs::file_size(path("map.tif"));
  fs::copy_file(path("map.tif"), path("short.tif"));
  fs::resize_file(path("short.tif"), size / 2);
  const std::string truncated = inputErrorOf(path("short.tif"));
  EXPECT_NE(truncated.find("short.tif"), std::string::npos) << truncated;
  EXPECT_NE(truncated.find("truncated or corrupt"), std::string::npos) << truncated;

  fs::copy_file(path("map.tif"), path("flipped.tif"));
  {
    std::fstream file(path("flipped.tif"), std::ios::in | std::ios::out | std::ios::binary);
    file.seekg(static_cast<std::streamoff>(size / 2));
    const char byte = static_cast<char>(file.get() ^ 0x40);
    file.seekp(static_cast<std::streamoff>(size / 2));
    file.put(byte);
  }
  const std::string corrupt = inputErrorOf(path("flipped.tif"));
  EXPECT_NE(corrupt.find("AAL_PIXEL_CHECKSUM"), std::string::npos) << corrupt;

  const std::vector<float> plain(8 * 6 * 4, 0.5f);
  writeGeoTiff(path("plain.tif"), RasterImage{8, 6, 4, RasterSampleType::Float32, plain.data()},
               utm());
  EXPECT_NE(inputErrorOf(path("plain.tif")).find("not made by aal-bake"), std::string::npos);
  writeFloatGeoTiff(path("one.tif"), 8, 6, plain.data(), utm());
  EXPECT_NE(inputErrorOf(path("one.tif")).find("has 1 bands"), std::string::npos);
  EXPECT_NE(inputErrorOf(path("none.tif")).find("does not exist"), std::string::npos);
}

}  // namespace
}  // namespace aal
