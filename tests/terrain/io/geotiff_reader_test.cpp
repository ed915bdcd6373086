// GeoTIFF and plain TIFF input: sample types, layouts, georeferencing rules
// and bad files. Files are written by the tests with libtiff + libgeotiff.
#include <gtest/gtest.h>

#include <GeographicLib/UTMUPS.hpp>

#include <cmath>
#include <fstream>
#include <limits>

#include "dem_loader.h"
#include "dem_test_util.h"
#include "georeference.h"
#include "test_tiff.h"

namespace aal {
namespace {

using test::SampleKind;
using test::TestTiff;

constexpr double kArcSec3 = 1.0 / 1200.0;

class GeoTiffReader : public ::testing::Test {
 protected:
  std::string write(const TestTiff& t, const std::string& name = "dem.tif") {
    const std::string path = (dir_.path() / name).string();
    test::writeTestTiff(path, t);
    return path;
  }
  // A geographic WGS84 grid, 3" cells, north-west corner at (lon, lat).
  static TestTiff geographic(double lon = -84.0, double lat = 37.0) {
    TestTiff t;
    t.modelType = 2;
    t.rasterType = 1;
    t.geographicType = 4326;
    t.pixelScale = {kArcSec3, kArcSec3, 0};
    t.tiePoints = {0, 0, 0, lon, lat, 0};
    return t;
  }
  static TestTiff projected(double cell, double x, double y) {
    TestTiff t;
    t.modelType = 1;
    t.rasterType = 1;
    t.pixelScale = {cell, cell, 0};
    t.tiePoints = {0, 0, 0, x, y, 0};
    return t;
  }
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

struct SampleCase {
  SampleKind kind;
  double first, step;  // values first + i * step
};

class GeoTiffSampleTypes : public GeoTiffReader,
                           public ::testing::WithParamInterface<SampleCase> {};

TEST_P(GeoTiffSampleTypes, HeightsRoundTripUnscaled) {
  TestTiff t = geographic();
  t.kind = GetParam().kind;
  t.values.resize(static_cast<size_t>(t.width * t.height));
  for (size_t i = 0; i < t.values.size(); ++i) t.values[i] = GetParam().first + i * GetParam().step;
  const Heightfield f = loadDem(write(t), warnings_.options());
  ASSERT_EQ(f.width, t.width);
  ASSERT_EQ(f.height, t.height);
  EXPECT_EQ(f.format, "GeoTIFF");
  for (size_t i = 0; i < t.values.size(); ++i) {
    EXPECT_EQ(f.z[i], static_cast<float>(t.values[i])) << "texel " << i;
  }
  EXPECT_EQ(f.voidCount, 0u);
  EXPECT_TRUE(f.voidMask.empty());
}

// Large magnitudes catch OpenImageIO's int -> [0, 1] float rescaling.
INSTANTIATE_TEST_SUITE_P(AllTypes, GeoTiffSampleTypes,
                         ::testing::Values(SampleCase{SampleKind::Int8, -100, 9},
                                           SampleCase{SampleKind::UInt8, 40, 11},
                                           SampleCase{SampleKind::Int16, -32000, 3001},
                                           SampleCase{SampleKind::UInt16, 300, 3401},
                                           SampleCase{SampleKind::Int32, -4000000, 400000},
                                           SampleCase{SampleKind::UInt32, 1000, 2000000},
                                           SampleCase{SampleKind::Float32, -431.25, 123.5},
                                           SampleCase{SampleKind::Float64, 8848.125, -517.75}));

TEST_F(GeoTiffReader, StripsTilesAndCompressionGiveTheSameHeights) {
  TestTiff t = geographic();
  t.width = 40;  // not a multiple of the 16-texel tiles
  t.height = 37;
  t.kind = SampleKind::Int16;
  const Heightfield plain = loadDem(write(t, "plain.tif"), warnings_.options());
  for (const uint16_t compression : {COMPRESSION_LZW, COMPRESSION_ADOBE_DEFLATE}) {
    for (const bool tiled : {false, true}) {
      t.compression = compression;
      t.tiled = tiled;
      const Heightfield f = loadDem(write(t, "variant.tif"), warnings_.options());
      EXPECT_EQ(f.z, plain.z) << "compression " << compression << " tiled " << tiled;
    }
  }
  EXPECT_EQ(plain.z[static_cast<size_t>(36 * 40 + 39)],
            static_cast<float>((36 * 40 + 39) * 7 - 20));
}

TEST_F(GeoTiffReader, ReadsTheFirstImageNotItsOverviews) {
  TestTiff t = geographic();
  t.width = 32;
  t.height = 32;
  t.overviews = 2;
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.width, 32);
  EXPECT_EQ(f.z[5], static_cast<float>(5 * 7 - 20));
}

TEST_F(GeoTiffReader, MultiBandImageUsesBandOneAndWarns) {
  TestTiff t = geographic();
  t.samplesPerPixel = 3;
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.z[3], static_cast<float>(3 * 7 - 20));
  EXPECT_TRUE(warnings_.any("3 channels")) << ::testing::PrintToString(warnings_.messages);
}

TEST_F(GeoTiffReader, PixelIsAreaPutsTexelCentresHalfACellIn) {
  TestTiff t = geographic(-84.0, 37.0);
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  EXPECT_EQ(f.geo.epsg, 4326);
  EXPECT_NEAR(f.geo.originX, -84.0 + 0.5 * kArcSec3, 1e-12);
  EXPECT_NEAR(f.geo.originY, 37.0 - 0.5 * kArcSec3, 1e-12);
  EXPECT_NEAR(f.geo.stepX, kArcSec3, 1e-15);
  EXPECT_TRUE(f.geo.hasCenter);
  EXPECT_NEAR(f.geo.centerLonDeg, -84.0 + 0.5 * t.width * kArcSec3, 1e-12);
  EXPECT_NEAR(f.geo.centerLatDeg, 37.0 - 0.5 * t.height * kArcSec3, 1e-12);
}

TEST_F(GeoTiffReader, PixelIsPointPutsTheTiePointOnTheTexelCentre) {
  TestTiff t = geographic(-84.0, 37.0);
  t.rasterType = 2;
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_NEAR(f.geo.originX, -84.0, 1e-12);
  EXPECT_NEAR(f.geo.originY, 37.0, 1e-12);
}

TEST_F(GeoTiffReader, TiePointMayNameAnyRasterPoint) {
  TestTiff t = projected(10.0, 5000.0, 9000.0);
  t.tiePoints = {2, 3, 0, 5000.0, 9000.0, 0};  // raster (2, 3) -> (5000, 9000)
  t.projectedType = 32616;
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_NEAR(f.geo.originX, 5000.0 - 1.5 * 10.0, 1e-9);
  EXPECT_NEAR(f.geo.originY, 9000.0 + 2.5 * 10.0, 1e-9);
}

TEST_F(GeoTiffReader, GeographicSpacingIsMetricPerRow) {
  TestTiff t = geographic(-84.0, 37.0);
  t.height = 7;
  const Heightfield f = loadDem(write(t), warnings_.options());
  ASSERT_EQ(f.rowCellSizeXM.size(), 7u);
  for (int row = 0; row < 7; ++row) {
    const double lat = f.geo.originY - row * kArcSec3;
    EXPECT_NEAR(f.rowCellSizeXM[static_cast<size_t>(row)], parallelArcM(lat, kArcSec3), 1e-9);
  }
  EXPECT_LT(f.rowCellSizeXM.front(), f.rowCellSizeXM.back());  // narrower to the north
  EXPECT_NEAR(f.cellSizeXM, parallelArcM(f.geo.centerLatDeg, kArcSec3), 1e-9);
  EXPECT_NEAR(f.cellSizeYM, 92.47, 0.02);
}

TEST_F(GeoTiffReader, ProjectedFeetAreConvertedToMetres) {
  TestTiff t = projected(10.0, 1000.0, 2000.0);
  t.linearUnits = 9002;
  Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 3.048);
  EXPECT_DOUBLE_EQ(f.cellSizeYM, 3.048);
  EXPECT_DOUBLE_EQ(f.geo.linearUnitM, 0.3048);
  t.linearUnits = 9003;  // US survey foot
  f = loadDem(write(t), warnings_.options());
  EXPECT_NEAR(f.cellSizeXM, 10.0 * 1200.0 / 3937.0, 1e-12);
  t.linearUnits = 32767;
  t.linearUnitSizeM = 2.5;
  f = loadDem(write(t), warnings_.options());
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 25.0);
  EXPECT_FALSE(f.geo.hasCenter);  // no EPSG code: no geographic centre
}

TEST_F(GeoTiffReader, ProjectedWithoutUnitAssumesMetresAndWarns) {
  TestTiff t = projected(5.0, 0.0, 0.0);
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 5.0);
  EXPECT_TRUE(warnings_.any("assuming metres"));
}

TEST_F(GeoTiffReader, UtmGridGetsItsGeographicCentre) {
  int zone = 0;
  bool north = false;
  double x = 0, y = 0;
  GeographicLib::UTMUPS::Forward(36.6, -84.2, zone, north, x, y);
  ASSERT_EQ(zone, 16);
  TestTiff t = projected(30.0, 0, 0);
  t.width = 11;
  t.height = 9;
  t.projectedType = 32600 + zone;
  // Texel (5, 4) is the centre; its centre is (x, y).
  t.tiePoints = {0, 0, 0, x - 5.5 * 30.0, y + 4.5 * 30.0, 0};
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_TRUE(warnings_.messages.empty()) << ::testing::PrintToString(warnings_.messages);
  EXPECT_EQ(f.geo.epsg, 32616);
  ASSERT_TRUE(f.geo.hasCenter);
  EXPECT_NEAR(f.geo.centerLatDeg, 36.6, 1e-8);
  EXPECT_NEAR(f.geo.centerLonDeg, -84.2, 1e-8);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 30.0);
}

TEST_F(GeoTiffReader, SouthernUtmAndUpsGridsGetTheirCentres) {
  struct Case {
    double lat, lon;
    int epsg;
  };
  for (const Case c :
       {Case{-33.9, 18.4, 32734}, Case{87.0, 40.0, 32661}, Case{-85.0, 10.0, 32761}}) {
    int zone = 0;
    bool north = false;
    double x = 0, y = 0;
    GeographicLib::UTMUPS::Forward(c.lat, c.lon, zone, north, x, y);
    TestTiff t = projected(100.0, x - 2.5 * 100.0, y + 1.5 * 100.0);
    t.height = 3;
    t.projectedType = c.epsg;
    const Heightfield f = loadDem(write(t), warnings_.options());
    ASSERT_TRUE(f.geo.hasCenter) << c.epsg;
    EXPECT_NEAR(f.geo.centerLatDeg, c.lat, 1e-8) << c.epsg;
    EXPECT_NEAR(f.geo.centerLonDeg, c.lon, 1e-8) << c.epsg;
  }
}

TEST_F(GeoTiffReader, ModelTransformationPlacesTheGrid) {
  TestTiff t;
  t.modelType = 1;
  t.projectedType = 32616;
  t.transformation = {20, 0, 0, 700000, 0, -25, 0, 4000000, 0, 0, 0, 0, 0, 0, 0, 1};
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 20.0);
  EXPECT_DOUBLE_EQ(f.cellSizeYM, 25.0);
  EXPECT_DOUBLE_EQ(f.geo.originX, 700010.0);
  EXPECT_DOUBLE_EQ(f.geo.originY, 3999987.5);
}

TEST_F(GeoTiffReader, SouthUpGridIsFlippedToNorthUp) {
  TestTiff t = projected(10.0, 0.0, 0.0);
  t.pixelScale = {10.0, -10.0, 0};  // row 0 is the southern edge, at y = 0
  const Heightfield f = loadDem(write(t), warnings_.options());
  const std::vector<double> v = test::rampValues(t.width, t.height);
  for (int y = 0; y < t.height; ++y) {
    for (int x = 0; x < t.width; ++x) {
      EXPECT_EQ(f.at(x, y),
                static_cast<float>(v[static_cast<size_t>((t.height - 1 - y) * t.width + x)]));
    }
  }
  EXPECT_DOUBLE_EQ(f.geo.originY, (t.height - 0.5) * 10.0);
  EXPECT_DOUBLE_EQ(f.geo.stepY, 10.0);
}

TEST_F(GeoTiffReader, GdalNodataMarksVoidsWhichAreFilled) {
  TestTiff t = geographic();
  t.kind = SampleKind::Int16;
  t.values = test::rampValues(t.width, t.height);
  t.values[0] = t.values[7] = t.values[8] = -32768;
  t.gdalNodata = "-32768";
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.voidCount, 3u);
  ASSERT_EQ(f.voidMask.size(), f.texelCount());
  for (size_t i = 0; i < f.texelCount(); ++i) {
    const bool isVoid = i == 0 || i == 7 || i == 8;
    EXPECT_EQ(f.voidMask[i] != 0, isVoid) << i;
    if (!isVoid) {
      EXPECT_EQ(f.z[i], static_cast<float>(t.values[i]));
    }
  }
  EXPECT_EQ(f.z[0], f.z[1]);  // nearest valid: the texel to the east
  EXPECT_GT(f.z[7], -1000.0f);
}

TEST_F(GeoTiffReader, Float32NodataMatchesInItsOwnPrecision) {
  TestTiff t = geographic();
  t.values = test::rampValues(t.width, t.height);
  t.values[4] = -std::numeric_limits<float>::max();
  t.gdalNodata = "-3.4028234663852886e+38";
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.voidCount, 1u);
  EXPECT_TRUE(f.isVoid(4, 0));
  EXPECT_TRUE(test::allFinite(f));
}

TEST_F(GeoTiffReader, NanAndInfinityAreVoids) {
  TestTiff t;  // plain float TIFF, no georeferencing
  t.values = test::rampValues(t.width, t.height);
  t.values[2] = std::numeric_limits<double>::quiet_NaN();
  t.values[9] = std::numeric_limits<double>::infinity();
  t.values[10] = -std::numeric_limits<double>::infinity();
  t.kind = SampleKind::Float64;
  t.values[11] = 1e300;  // beyond float range
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.format, "TIFF");
  EXPECT_EQ(f.voidCount, 4u);
  EXPECT_TRUE(test::allFinite(f));
}

TEST_F(GeoTiffReader, UnparsableNodataIsIgnoredWithAWarning) {
  TestTiff t = geographic();
  t.gdalNodata = "none";
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.voidCount, 0u);
  EXPECT_TRUE(warnings_.any("GDAL_NODATA 'none'"));
}

TEST_F(GeoTiffReader, VerticalFeetScaleHeightsUnlessOverridden) {
  TestTiff t = geographic();
  t.verticalUnits = 9002;
  const std::string path = write(t);
  Heightfield f = loadDem(path, warnings_.options());
  EXPECT_DOUBLE_EQ(f.zScale, 0.3048);
  EXPECT_FLOAT_EQ(f.z[5], static_cast<float>((5 * 7 - 20) * 0.3048));
  DemLoadOptions o = warnings_.options();
  o.zScale = 2.0;
  f = loadDem(path, o);
  EXPECT_FLOAT_EQ(f.z[5], static_cast<float>((5 * 7 - 20) * 2.0));
}

TEST_F(GeoTiffReader, CellSizeOverrideWinsOverGeographicSpacing) {
  DemLoadOptions o = warnings_.options();
  o.cellSizeM = 12.5;
  const Heightfield f = loadDem(write(geographic()), o);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 12.5);
  EXPECT_DOUBLE_EQ(f.cellSizeYM, 12.5);
  EXPECT_TRUE(f.rowCellSizeXM.empty());
  EXPECT_TRUE(f.geo.hasCenter);  // the location is still known
}

// ---- bad georeferencing ----------------------------------------------------

TEST_F(GeoTiffReader, GeocentricModelIsRefused) {
  TestTiff t = geographic();
  t.modelType = 3;
  const std::string path = write(t);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "inconsistent georeferencing", "geocentric"});
}

TEST_F(GeoTiffReader, GeoKeysWithoutPlacementAreRefused) {
  TestTiff t = geographic();
  t.pixelScale.clear();
  t.tiePoints.clear();
  const std::string path = write(t);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "without pixel scale, tie point or transformation"});
}

TEST_F(GeoTiffReader, TiePointsWithoutPixelScaleAreRefused) {
  TestTiff t = geographic();
  t.pixelScale.clear();
  t.tiePoints = {0, 0, 0, -84, 37, 0, 4, 3, 0, -83.9, 36.9, 0};
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"ground control points"});
}

TEST_F(GeoTiffReader, ZeroOrNonFinitePixelScaleIsRefused) {
  TestTiff t = geographic();
  t.pixelScale = {0.0, kArcSec3, 0};
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"inconsistent georeferencing", "pixel scale"});
  t.pixelScale = {kArcSec3, std::numeric_limits<double>::quiet_NaN(), 0};
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"inconsistent georeferencing", "finite"});
}

TEST_F(GeoTiffReader, LatitudesBeyondThePoleAreRefused) {
  TestTiff t = geographic(10.0, 90.5);
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"inconsistent georeferencing", "beyond +-90"});
}

TEST_F(GeoTiffReader, GeographicModelWithProjectedCodeIsRefused) {
  TestTiff t = geographic();
  t.projectedType = 32616;
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"model type is geographic but ProjectedCSTypeGeoKey is 32616"});
}

TEST_F(GeoTiffReader, UnknownUnitsAreRefused) {
  TestTiff t = projected(10.0, 0, 0);
  t.linearUnits = 9999;
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"unsupported linear unit code 9999"});
  TestTiff g = geographic();
  g.angularUnits = 9998;
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(g), warnings_.options()); }),
                      {"unsupported angular unit code 9998"});
}

TEST_F(GeoTiffReader, RotatedTransformationIsRefused) {
  TestTiff t;
  t.modelType = 1;
  t.transformation = {20, 1, 0, 700000, 1, -25, 0, 4000000, 0, 0, 0, 0, 0, 0, 0, 1};
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"rotates or shears"});
}

TEST_F(GeoTiffReader, UtmCentreOutsideTheZoneIsRefused) {
  TestTiff t = projected(30.0, 5.0e7, 1.0e9);
  t.projectedType = 32616;
  test::expectMessage(test::inputErrorOf([&] { loadDem(write(t), warnings_.options()); }),
                      {"inconsistent georeferencing", "outside UTM zone 16 north"});
}

TEST_F(GeoTiffReader, PlacementWithoutModelTypeIsIgnoredWithAWarning) {
  TestTiff t;
  t.pixelScale = {2, 2, 0};
  t.tiePoints = {0, 0, 0, 0, 0, 0};
  const Heightfield f = loadDem(write(t), warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::None);
  EXPECT_TRUE(warnings_.any("no model type"));
}

// ---- bad files -------------------------------------------------------------

TEST_F(GeoTiffReader, TruncatedPixelDataIsRefused) {
  const std::string path = (dir_.path() / "cut.tif").string();
  std::vector<int16_t> pixels(64 * 64, 100);
  test::writeHandmadeInt16Tiff(path, 64, 64, pixels, pixels.size() * 2);
  EXPECT_EQ(loadDem(path, warnings_.options()).z[4095], 100.0f);  // the intact file reads
  test::writeHandmadeInt16Tiff(path, 64, 64, pixels, 1000);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }), {path});
}

TEST_F(GeoTiffReader, FileCutInHalfIsRefused) {
  TestTiff t = geographic();
  t.width = 64;
  t.height = 64;
  const std::string path = write(t);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  test::writeBytes(path, bytes.substr(0, bytes.size() / 2));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "not a readable TIFF"});
}

TEST_F(GeoTiffReader, CorruptCompressedDataIsRefused) {
  TestTiff t = geographic();
  t.width = 64;
  t.height = 64;
  t.compression = COMPRESSION_ADOBE_DEFLATE;
  t.values = test::rampValues(64, 64, 0.37);
  const std::string path = write(t);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  for (size_t i = 16; i < bytes.size() / 2; ++i) bytes[i] = static_cast<char>(i * 31);
  test::writeBytes(path, bytes);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }), {path});
}

TEST_F(GeoTiffReader, HugeDimensionsAreRefusedBeforeReading) {
  const std::string path = (dir_.path() / "huge.tif").string();
  test::writeHandmadeInt16Tiff(path, 70000, 10, {}, 0);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "70000 x 10", "limit of 65536 texels per side"});
  test::writeHandmadeInt16Tiff(path, 50000, 50000, {}, 0);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "2500000000 texels", "limit of 2147483648"});
}

TEST_F(GeoTiffReader, RowsPerStripFarBeyondTheHeightIsRefused) {
  // Compressed (libtiff re-chops uncompressed single strips), one 2-row strip
  // whose RowsPerStrip is then patched: OpenImageIO would size its strip
  // buffer by it, 60000 x 70000 x 4 bytes.
  TestTiff t;
  t.width = 60000;
  t.height = 2;
  t.compression = COMPRESSION_ADOBE_DEFLATE;
  t.values.assign(120000, 5.0);
  const std::string path = write(t);
  EXPECT_EQ(loadDem(path, warnings_.options()).z[119999], 5.0f);
  test::patchTiffTag(path, TIFFTAG_ROWSPERSTRIP, 70000);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {path, "inconsistent TIFF layout", "strips of 70000 rows (RowsPerStrip)"});
  // A RowsPerStrip a little above the height, or 2^32 - 1 ("one strip"), is fine.
  test::patchTiffTag(path, TIFFTAG_ROWSPERSTRIP, 8);
  EXPECT_EQ(loadDem(path, warnings_.options()).z[119999], 5.0f);
  test::patchTiffTag(path, TIFFTAG_ROWSPERSTRIP, 0xffffffffu);
  EXPECT_EQ(loadDem(path, warnings_.options()).z[0], 5.0f);
}

TEST_F(GeoTiffReader, HugeTilesForASmallImageAreRefused) {
  TestTiff t;
  t.tiled = true;
  t.compression = COMPRESSION_ADOBE_DEFLATE;
  const std::string path = write(t);
  EXPECT_EQ(loadDem(path, warnings_.options()).z[3], static_cast<float>(3 * 7 - 20));
  test::patchTiffTag(path, TIFFTAG_TILEWIDTH, 65536);
  test::patchTiffTag(path, TIFFTAG_TILELENGTH, 65536);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {path, "inconsistent TIFF layout", "65536 x 65536 tiles"});
}

}  // namespace
}  // namespace aal
