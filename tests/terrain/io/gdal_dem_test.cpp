// DEMs read through GDAL (terrain/io/dem_source.h): the files GIS users
// have, made here with GDAL's own API, read right — compared with GDAL's
// statistics — and what is not a DEM refused with a way out.
#include <gtest/gtest.h>

#include <gdal_utils.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <numbers>
#include <thread>
#include <utility>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/georeference.h"
#include "aperture/tests/terrain/io/dem_test_util.h"
#include "aperture/tests/terrain/io/gdal_raster.h"
#include "aperture/tests/terrain/io/hostile_files.h"

namespace aal {
namespace {

class GdalDem : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  std::string write(const std::string& name, const test::GdalRaster& r,
                    const std::string& driver = "GTiff") {
    EXPECT_TRUE(test::writeGdalRaster(path(name), r, driver));
    return path(name);
  }
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

struct Range {
  double min = std::numeric_limits<double>::infinity(), max = -min, mean = 0;
};
// Over valid texels, in the file's unit (z scale undone).
Range rangeOf(const Heightfield& f) {
  Range r;
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < f.z.size(); ++i) {
    if (!f.voidMask.empty() && f.voidMask[i]) continue;
    const double z = f.z[i] / f.zScale;
    r.min = std::min(r.min, z);
    r.max = std::max(r.max, z);
    sum += z;
    ++n;
  }
  r.mean = n ? sum / n : 0;
  return r;
}

void expectGdalStatistics(const std::string& path, const Heightfield& f, double tolerance) {
  const test::GdalStatistics s = test::gdalStatistics(path);
  const Range r = rangeOf(f);
  EXPECT_NEAR(r.min, s.min, tolerance) << path;
  EXPECT_NEAR(r.max, s.max, tolerance) << path;
  EXPECT_NEAR(r.mean, s.mean, tolerance + 1e-6 * std::abs(s.mean)) << path;
}

test::GdalRaster utm(int width, int height) {
  test::GdalRaster r;
  r.width = width;
  r.height = height;
  r.hasTransform = true;
  const double t[6] = {500000, 30, 0, 4000000, 0, -30};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:32616";
  return r;
}

// The one-degree tile N36W085 (sample centres on its edges, as SRTM and
// DTED have them): posts x posts int16 samples, WGS84.
test::GdalRaster oneDegreeTile(int posts) {
  test::GdalRaster r;
  r.width = r.height = posts;
  r.type = GDT_Int16;
  r.hasTransform = true;
  const double step = 1.0 / (posts - 1);
  const double t[6] = {-85 - step / 2, step, 0, 37 + step / 2, 0, -step};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:4326";
  return r;
}

TEST_F(GdalDem, AlphaBandIsVoidsNotHeights) {
  // What `gdalwarp -dstalpha -co TILED=YES` writes: heights 0..1000 m and
  // an alpha band, 0 outside the warped footprint.
  test::GdalRaster r = utm(64, 48);
  r.bands = 2;
  r.value = [](int band, int c, int row) {
    if (band == 2) return c < 8 ? 0.0 : 255.0;
    return 1000.0 * (c + 64 * row) / (64 * 48 - 1);
  };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(2)->SetColorInterpretation(GCI_AlphaBand); };
  r.creationOptions = {"TILED=YES", "ALPHA=YES"};
  const std::string p = write("alpha.tif", r);
  {
    // GDAL itself does not take a float32 alpha band for a mask.
    GDALDatasetUniquePtr ds(GDALDataset::Open(p.c_str(), GDAL_OF_RASTER));
    EXPECT_EQ(ds->GetRasterBand(2)->GetColorInterpretation(), GCI_AlphaBand);
  }
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.voidCount, 8u * 48u);
  EXPECT_TRUE(f.isVoid(7, 20));
  EXPECT_FALSE(f.isVoid(8, 20));
  EXPECT_LE(rangeOf(f).max, 1000.0);
  EXPECT_NEAR(f.at(63, 47), 1000.0f, 1e-3);
  EXPECT_FALSE(warnings_.any("bands")) << "an alpha band is not an extra band";
}

TEST_F(GdalDem, ByteAlphaBandIsVoidsToo) {
  test::GdalRaster r = utm(16, 16);
  r.type = GDT_Byte;
  r.bands = 2;
  r.value = [](int band, int c, int row) { return band == 2 ? (row < 3 ? 0.0 : 255.0) : c + row; };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(2)->SetColorInterpretation(GCI_AlphaBand); };
  r.creationOptions = {"ALPHA=YES"};
  const Heightfield f = loadDem(write("alpha8.tif", r), warnings_.options());
  EXPECT_EQ(f.voidCount, 48u);
  EXPECT_EQ(f.at(15, 15), 30.0f);
}

TEST_F(GdalDem, InternalMaskIsVoids) {
  test::GdalRaster r = utm(32, 32);
  r.creationOptions = {"TILED=YES"};
  r.extra = [](GDALDataset& ds) {
    CPLSetThreadLocalConfigOption("GDAL_TIFF_INTERNAL_MASK", "YES");
    ds.CreateMaskBand(GMF_PER_DATASET);
    std::vector<GByte> mask(32 * 32, 255);
    for (int i = 0; i < 32; ++i) mask[static_cast<size_t>(i) * 32 + i] = 0;  // the diagonal
    EXPECT_EQ(ds.GetRasterBand(1)->GetMaskBand()->RasterIO(GF_Write, 0, 0, 32, 32, mask.data(), 32,
                                                           32, GDT_Byte, 0, 0, nullptr),
              CE_None);
  };
  const std::string p = write("masked.tif", r);
  CPLSetThreadLocalConfigOption("GDAL_TIFF_INTERNAL_MASK", nullptr);
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.voidCount, 32u);
  EXPECT_TRUE(f.isVoid(5, 5));
  EXPECT_FALSE(f.isVoid(5, 6));
  // GDAL 3.6's statistics ignore masks: the masked corners (0, 0) and
  // (31, 31) would be the extremes.
  EXPECT_EQ(rangeOf(f).min, 1.0);
  EXPECT_EQ(rangeOf(f).max, 340.0);
}

TEST_F(GdalDem, NBitSamplesKeepTheirValues) {
  test::GdalRaster r = utm(16, 8);
  r.type = GDT_UInt16;
  r.value = [](int, int c, int row) { return c == 0 && row == 0 ? 1000.0 : 7.0 * c + row; };
  r.creationOptions = {"NBITS=12"};
  const std::string p = write("nbits.tif", r);
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.at(0, 0), 1000.0f);
  EXPECT_EQ(f.at(15, 7), 112.0f);
  expectGdalStatistics(p, f, 0.0);
}

TEST_F(GdalDem, ScaleAndOffsetAreApplied) {
  test::GdalRaster r = utm(8, 4);
  r.type = GDT_Int16;
  r.value = [](int, int c, int row) { return 12345.0 + c - row; };
  r.extra = [](GDALDataset& ds) {
    ds.GetRasterBand(1)->SetScale(0.1);
    ds.GetRasterBand(1)->SetOffset(-100.0);
  };
  const std::string p = write("scaled.tif", r);
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_NEAR(f.at(0, 0), 1134.5f, 1e-3);
  EXPECT_NEAR(f.at(7, 0), 1135.2f, 1e-3);
  expectGdalStatistics(p, f, 1e-3);
}

TEST_F(GdalDem, OneRowFloat64) {
  test::GdalRaster r = utm(5, 1);
  r.type = GDT_Float64;
  r.value = [](int, int c, int) { return 100.25 + c; };
  const Heightfield f = loadDem(write("row.tif", r), warnings_.options());
  ASSERT_EQ(f.height, 1);
  for (int c = 0; c < 5; ++c) EXPECT_EQ(f.at(c, 0), 100.25f + c);
}

TEST_F(GdalDem, Int64AndInt8Samples) {
  test::GdalRaster r = utm(4, 2);
  r.type = GDT_Int64;
  r.value = [](int, int c, int row) { return row == 1 && c == 3 ? -9999.0 : 1000.0 * c - 5; };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValueAsInt64(-9999); };
  Heightfield f = loadDem(write("i64.tif", r), warnings_.options());
  EXPECT_EQ(f.at(2, 0), 1995.0f);
  EXPECT_EQ(f.voidCount, 1u);
  EXPECT_TRUE(f.isVoid(3, 1));

  r.type = GDT_Byte;
  r.value = [](int, int c, int) { return c == 0 ? 200.0 : 5.0; };  // -56 as int8
  r.creationOptions = {"PIXELTYPE=SIGNEDBYTE"};
  r.extra = nullptr;
  f = loadDem(write("i8.tif", r), warnings_.options());
  EXPECT_EQ(f.at(0, 0), -56.0f);
  EXPECT_EQ(f.at(1, 0), 5.0f);
}

TEST_F(GdalDem, PaletteRgbAndComplexAreRefusedWithAWayOut) {
  test::GdalRaster palette = utm(4, 4);
  palette.type = GDT_Byte;
  palette.extra = [](GDALDataset& ds) {
    GDALColorTable table;
    for (int i = 0; i < 256; ++i) {
      const GDALColorEntry e{static_cast<short>(i), 0, 0, 255};
      table.SetColorEntry(i, &e);
    }
    ds.GetRasterBand(1)->SetColorTable(&table);
  };
  const std::string pal = write("palette.tif", palette);
  test::expectMessage(test::inputErrorOf([&] { loadDem(pal); }),
                      {pal, "palette", "gdal_translate -b"});

  test::GdalRaster rgb = utm(4, 4);
  rgb.type = GDT_Byte;
  rgb.bands = 3;
  rgb.creationOptions = {"PHOTOMETRIC=RGB"};
  const std::string colour = write("photo.tif", rgb);
  test::expectMessage(test::inputErrorOf([&] { loadDem(colour); }),
                      {colour, "RGB", "gdal_translate -b"});

  test::GdalRaster complex = utm(4, 4);
  complex.type = GDT_CFloat32;
  const std::string c = write("complex.tif", complex);
  test::expectMessage(test::inputErrorOf([&] { loadDem(c); }), {c, "complex", "gdal_translate -b"});
}

TEST_F(GdalDem, ExtraBandsAreIgnoredWithAWarning) {
  test::GdalRaster r = utm(4, 4);
  r.bands = 2;
  r.value = [](int band, int c, int) { return band * 100.0 + c; };
  const Heightfield f = loadDem(write("two.tif", r), warnings_.options());
  EXPECT_EQ(f.at(3, 0), 103.0f);
  EXPECT_TRUE(warnings_.any("2 bands; heights are read from band 1"));
}

TEST_F(GdalDem, PngTransparentColourIsNodata) {
  test::GdalRaster r;
  r.width = 6;
  r.height = 2;
  r.type = GDT_UInt16;
  r.value = [](int, int c, int) { return c == 2 ? 0.0 : 500.0 + c; };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValue(0); };
  const std::string p = write("dem.png", r, "PNG");
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.format, "Portable Network Graphics");
  EXPECT_EQ(f.voidCount, 2u);
  EXPECT_TRUE(f.isVoid(2, 1));
  EXPECT_EQ(f.at(5, 0), 505.0f);
  EXPECT_TRUE(warnings_.any("not georeferenced"));
}

TEST_F(GdalDem, FeetFromAnEpsgCodeAlone) {
  // California zone V in US survey feet, written with GeoTIFF 1.1 keys:
  // only ProjectedCSTypeGeoKey 2229 says that the unit is the foot.
  test::GdalRaster r;
  r.hasTransform = true;
  const double t[6] = {6500000, 100, 0, 1900000, 0, -100};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:2229";
  r.creationOptions = {"GEOTIFF_VERSION=1.1"};
  const Heightfield f = loadDem(write("feet.tif", r), warnings_.options());
  EXPECT_EQ(f.geo.epsg, 2229);
  EXPECT_NEAR(f.geo.linearUnitM, 1200.0 / 3937.0, 1e-12);
  EXPECT_NEAR(f.cellSizeXM, 30.48, 0.01);
  EXPECT_TRUE(f.geo.hasCenter);
  EXPECT_NEAR(f.geo.centerLatDeg, 34.2, 0.5);  // Los Angeles
  EXPECT_NEAR(f.geo.centerLonDeg, -118.3, 0.5);
}

TEST_F(GdalDem, VerticalFeetFromTheBandUnit) {
  test::GdalRaster r = utm(4, 4);
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetUnitType("ft"); };
  const Heightfield f = loadDem(write("zfeet.tif", r), warnings_.options());
  EXPECT_DOUBLE_EQ(f.zScale, 0.3048);
  EXPECT_EQ(f.zUnitName, "ft");
  EXPECT_NEAR(f.at(1, 2), 21.0f * 0.3048f, 1e-5);
}

TEST_F(GdalDem, ParisMeridianAndGrads) {
  // NTF (Paris), EPSG:4807: longitudes in grads east of Paris.
  test::GdalRaster r;
  r.width = r.height = 11;
  r.hasTransform = true;
  const double t[6] = {0.0 - 0.005, 0.01, 0, 54.0 + 0.005, 0, -0.01};  // grads
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:4807";
  const Heightfield f = loadDem(write("paris.tif", r), warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  ASSERT_TRUE(f.geo.hasCenter);
  // 53.95 grads = 48.555 degrees north; Paris is 2.33722917 degrees east.
  EXPECT_NEAR(f.geo.centerLatDeg, 53.95 * 0.9, 1e-9);
  EXPECT_NEAR(f.geo.centerLonDeg, 0.05 * 0.9 + 2.33722917, 1e-6);
  // 0.01 grad of latitude is 0.009 degrees: about 1 km.
  EXPECT_NEAR(f.cellSizeYM, meridianArcM(48.5, 48.509), 1.0);
}

TEST_F(GdalDem, AsciiGridWithAGeographicPrj) {
  const std::string p = path("dem.asc");
  test::writeBytes(p,
                   "ncols 3\nnrows 2\nxllcorner -84.5\nyllcorner 36.5\ncellsize 0.001\n"
                   "NODATA_value -9999\n1 2 3\n4 -9999 6\n");
  // An Arc/Info .prj in decimal degrees (ESRI WKT).
  test::writeBytes(
      path("dem.prj"),
      "GEOGCS[\"GCS_WGS_1984\",DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\",6378137.0,"
      "298.257223563]],PRIMEM[\"Greenwich\",0.0],UNIT[\"Degree\",0.0174532925199433]]");
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  EXPECT_EQ(f.voidCount, 1u);
  EXPECT_TRUE(f.isVoid(1, 1));
  EXPECT_NEAR(f.cellSizeYM, meridianArcM(36.5, 36.501), 0.01);  // ~111 m, not 0.001 m
  EXPECT_EQ(f.at(2, 0), 3.0f);
}

TEST_F(GdalDem, AsciiGridWithoutPrjIsMetres) {
  const std::string p = path("local.asc");
  test::writeBytes(p, "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 5\n1 2\n3 4\n");
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::Projected);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 5.0);
  EXPECT_FALSE(f.geo.hasCenter);
  EXPECT_TRUE(warnings_.any("no coordinate reference system"));
}

// DemSource finds the CRS on a thread of its own while the samples decode
// (docs/performance.md): what it gives must not depend on the order of the
// caller's requests, and its warnings come once, on the caller's thread.
TEST_F(GdalDem, CrsFoundWhileReadingEqualsTheCrsFoundFirst) {
  const std::string p = write("utm.tif", utm(64, 48));
  const DemSource readFirst(p, warnings_.options());
  const RawDem samples = readFirst.readAll();
  const DemSource describedFirst(p, warnings_.options());
  const RawDem& description = describedFirst.description();
  EXPECT_EQ(samples.geo.epsg, 32616);
  ASSERT_TRUE(samples.geo.srs && description.geo.srs);
  EXPECT_TRUE(samples.geo.srs->IsSame(description.geo.srs.get()));
  EXPECT_EQ(samples.geo.crsName, description.geo.crsName);
  EXPECT_DOUBLE_EQ(samples.geo.originX, description.geo.originX);
  EXPECT_DOUBLE_EQ(samples.geo.linearUnitM, description.geo.linearUnitM);
  // The spacing found beside the CRS is metricSpacing's, computed here.
  const MetricSpacing direct = metricSpacing(p, samples.geo, 64, 48);
  ASSERT_TRUE(samples.spacing.has_value());
  EXPECT_DOUBLE_EQ(samples.spacing->cellSizeXM, direct.cellSizeXM);
  EXPECT_DOUBLE_EQ(samples.spacing->cellSizeYM, direct.cellSizeYM);
  EXPECT_DOUBLE_EQ(samples.spacing->centerLatDeg, direct.centerLatDeg);
  EXPECT_TRUE(direct.hasCenter);
  // A window has its own centre: no whole-raster spacing rides along.
  EXPECT_FALSE(readFirst.read(8, 8, 16, 16).spacing.has_value());
}

TEST_F(GdalDem, CrsWarningsComeOnceOnTheCallersThread) {
  const std::string p = path("local.asc");
  test::writeBytes(p, "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 5\n1 2\n3 4\n");
  std::vector<std::thread::id> threads;
  DemLoadOptions options;
  options.warn = [&](const std::string& m) {
    if (m.find("no coordinate reference system") != std::string::npos) {
      threads.push_back(std::this_thread::get_id());
    }
  };
  const DemSource source(p, options);
  source.readAll();
  source.description();
  source.readAll();
  ASSERT_EQ(threads.size(), 1u);
  EXPECT_EQ(threads[0], std::this_thread::get_id());
}

TEST_F(GdalDem, GeocentricCrsIsRefusedWhenAsked) {
  test::GdalRaster r;
  r.hasTransform = true;
  const double t[6] = {4000000, 30, 0, 500000, 0, -30};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:4978";  // WGS 84 geocentric
  const std::string p = write("geocentric.tif", r);
  const std::string message = test::inputErrorOf([&] { loadDem(p, warnings_.options()); });
  EXPECT_NE(message.find("geocentric"), std::string::npos) << message;
  // Asked again, the same answer (the CRS is looked at once).
  const DemSource source(p, warnings_.options());
  EXPECT_THROW(source.description(), InputError);
  EXPECT_THROW(source.readAll(), InputError);
}

TEST_F(GdalDem, EsriWebMercatorGetsItsGroundSpacing) {
  // "WGS 1984 Web Mercator Auxiliary Sphere" as ArcGIS writes it.
  test::GdalRaster r;
  r.width = r.height = 21;
  r.hasTransform = true;
  // Around 60 N, 10 E: y = R ln tan(pi/4 + phi/2).
  const double R = 6378137.0, phi = 60.0 * std::numbers::pi / 180.0;
  const double x = R * 10.0 * std::numbers::pi / 180.0,
               y = R * std::log(std::tan(std::numbers::pi / 4 + phi / 2));
  const double t[6] = {x - 10.5 * 100, 100, 0, y + 10.5 * 100, 0, -100};
  std::copy(t, t + 6, r.transform);
  r.crs =
      "ESRI::PROJCS[\"WGS_1984_Web_Mercator_Auxiliary_Sphere\",GEOGCS[\"GCS_WGS_1984\","
      "DATUM[\"D_WGS_1984\",SPHEROID[\"WGS_1984\",6378137.0,298.257223563]],PRIMEM[\"Greenwich\","
      "0.0],UNIT[\"Degree\",0.0174532925199433]],PROJECTION[\"Mercator_Auxiliary_Sphere\"],"
      "PARAMETER[\"False_Easting\",0.0],PARAMETER[\"False_Northing\",0.0],PARAMETER["
      "\"Central_Meridian\",0.0],PARAMETER[\"Standard_Parallel_1\",0.0],PARAMETER["
      "\"Auxiliary_Sphere_Type\",0.0],UNIT[\"Meter\",1.0]]";
  const Heightfield f = loadDem(write("webmerc.tif", r), warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::Projected);
  ASSERT_TRUE(f.geo.hasCenter);
  EXPECT_NEAR(f.geo.centerLatDeg, 60.0, 1e-6);
  EXPECT_NEAR(f.geo.centerLonDeg, 10.0, 1e-6);
  // 100 m of Web Mercator at 60 N is 50 m on the ground (ellipsoidal: 50.1).
  EXPECT_NEAR(f.cellSizeXM, 50.1, 0.2);
  EXPECT_NEAR(f.cellSizeYM, 50.1, 0.2);
  EXPECT_TRUE(warnings_.any("stretches distances"));
}

TEST_F(GdalDem, CoordinatesBeyondTheEarthAreRefusedBeforeProj) {
  // Found by fuzz_load_dem: GDAL's Web Mercator shortcut wraps longitudes a
  // turn at a time, so x = 1e18 m hung the loader in PROJ's transform.
  test::GdalRaster r;
  r.width = r.height = 4;
  r.hasTransform = true;
  const double t[6] = {1e18, 30, 0, 80, 0, -30};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:3857";
  const std::string far = write("far.tif", r);
  test::expectMessage(test::inputErrorOf([&] { loadDem(far); }),
                      {far, "beyond any map of the Earth"});
  // A legitimate far corner: Web Mercator's own edge, 2.0e7 m.
  const double edge[6] = {-20037508.34, 30, 0, 80, 0, -30};
  std::copy(edge, edge + 6, r.transform);
  EXPECT_NO_THROW(loadDem(write("edge.tif", r), warnings_.options()));
}

TEST_F(GdalDem, CentreOfAnyProjectedCrs) {
  // ETRS89 / LAEA Europe: its false origin (4321000, 3210000) is 52 N, 10 E.
  test::GdalRaster r;
  r.width = r.height = 3;
  r.hasTransform = true;
  const double t[6] = {4321000 - 150, 100, 0, 3210000 + 150, 0, -100};
  std::copy(t, t + 6, r.transform);
  r.crs = "EPSG:3035";
  const Heightfield f = loadDem(write("laea.tif", r), warnings_.options());
  EXPECT_EQ(f.geo.epsg, 3035);
  ASSERT_TRUE(f.geo.hasCenter);
  EXPECT_NEAR(f.geo.centerLatDeg, 52.0, 1e-7);
  EXPECT_NEAR(f.geo.centerLonDeg, 10.0, 1e-7);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 100.0);  // LAEA's scale is ~1 at its origin
  EXPECT_TRUE(warnings_.messages.empty()) << ::testing::PrintToString(warnings_.messages);
}

TEST_F(GdalDem, SparseCogReadsItsHolesAsVoids) {
  test::GdalRaster r = utm(1024, 512);
  r.value = [](int, int c, int) { return c < 512 ? -9999.0 : 250.0; };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValue(-9999); };
  r.creationOptions = {"SPARSE_OK=TRUE", "BLOCKSIZE=256", "COMPRESS=DEFLATE"};
  const std::string p = write("sparse.tif", r, "COG");
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.voidCount, 512u * 512u);
  EXPECT_EQ(f.at(1000, 100), 250.0f);
  EXPECT_EQ(f.format, "GeoTIFF");
}

TEST_F(GdalDem, RotatedGridAndGcpsAreRefused) {
  test::GdalRaster r = utm(4, 4);
  r.transform[2] = 5.0;
  const std::string p = write("rotated.tif", r);
  test::expectMessage(test::inputErrorOf([&] { loadDem(p); }), {p, "rotated", "gdalwarp"});
}

TEST_F(GdalDem, SouthUpGridIsFlipped) {
  test::GdalRaster r = utm(3, 4);
  r.transform[3] = 4000000 - 120;
  r.transform[5] = 30;  // row 0 is the south
  const Heightfield f = loadDem(write("southup.tif", r), warnings_.options());
  EXPECT_EQ(f.at(1, 0), 31.0f);  // file row 3 is north
  EXPECT_EQ(f.at(1, 3), 1.0f);
  EXPECT_DOUBLE_EQ(f.geo.originY, 4000000 - 15);
}

TEST_F(GdalDem, HgtTileIsGeographicWithVoids) {
  test::GdalRaster r = oneDegreeTile(1201);
  r.value = [](int, int c, int row) { return c == 7 && row == 9 ? -32768.0 : c - row; };
  const std::string p = write("N36W085.hgt", r, "SRTMHGT");
  const Heightfield f = loadDem(p, warnings_.options());
  EXPECT_EQ(f.driver, "SRTMHGT");
  EXPECT_EQ(f.geo.epsg, 4326);
  EXPECT_DOUBLE_EQ(f.geo.originX, -85.0);
  EXPECT_EQ(f.voidCount, 1u);
  EXPECT_TRUE(f.isVoid(7, 9));
  EXPECT_EQ(f.at(1200, 0), 1200.0f);
  EXPECT_NEAR(f.cellSizeYM, meridianArcM(36.0, 37.0) / 1200, 1e-6);
}

TEST_F(GdalDem, ErdasImgNetCdfAndDtedRead) {
  test::GdalRaster r = oneDegreeTile(121);  // a DTED level 0 cell
  r.value = [](int, int c, int row) { return 200.0 + c + 2 * row; };
  for (const auto& [driver, name] : {std::pair<std::string, std::string>{"HFA", "dem.img"},
                                     {"netCDF", "dem.nc"},
                                     {"DTED", "dem.dt0"}}) {
    const std::string p = write(name, r, driver);
    const Heightfield f = loadDem(p, warnings_.options());
    EXPECT_EQ(f.driver, driver) << name;
    EXPECT_EQ(f.geo.crs, CrsKind::Geographic) << name;
    EXPECT_EQ(f.at(10, 20), 250.0f) << name;
    EXPECT_NEAR(f.geo.centerLatDeg, 36.5, 1e-6) << name;
    EXPECT_NEAR(f.geo.centerLonDeg, -84.5, 1e-6) << name;
    expectGdalStatistics(p, f, 1e-3);
  }
}

TEST_F(GdalDem, VrtMosaicReadsAsOne) {
  test::GdalRaster west = utm(8, 4), east = utm(8, 4);
  east.transform[0] += 8 * 30;
  east.value = [](int, int c, int row) { return 1000.0 + 10 * row + c; };
  const std::string a = write("west.tif", west), b = write("east.tif", east);
  const std::string vrt = path("mosaic.vrt");
  const char* sources[] = {a.c_str(), b.c_str()};
  GDALDatasetH mosaic = GDALBuildVRT(vrt.c_str(), 2, nullptr, sources, nullptr, nullptr);
  ASSERT_NE(mosaic, nullptr);
  GDALClose(mosaic);
  const Heightfield f = loadDem(vrt, warnings_.options());
  EXPECT_EQ(f.width, 16);
  EXPECT_EQ(f.format, "Virtual Raster");
  EXPECT_EQ(f.at(3, 2), 23.0f);
  EXPECT_EQ(f.at(11, 2), 1023.0f);
}

TEST_F(GdalDem, WindowsEqualTheWholeRead) {
  test::GdalRaster r = utm(300, 200);
  r.value = [](int, int c, int row) {
    return (c * 7 + row * 13) % 101 == 0 ? -1.0 : c * 0.5 + row;
  };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValue(-1); };
  r.creationOptions = {"TILED=YES", "BLOCKXSIZE=64", "BLOCKYSIZE=64", "COMPRESS=LZW"};
  const std::string p = write("tiles.tif", r);
  const DemSource source(p, warnings_.options());
  const RawDem whole = source.readAll();
  const RawDem window = source.read(70, 30, 100, 150);
  ASSERT_EQ(window.width, 100);
  ASSERT_EQ(window.height, 150);
  for (int row = 0; row < 150; ++row) {
    for (int c = 0; c < 100; ++c) {
      const size_t w = static_cast<size_t>(row) * 100 + c;
      const size_t o = static_cast<size_t>(row + 30) * 300 + c + 70;
      ASSERT_EQ(window.z[w], whole.z[o]) << c << "," << row;
      ASSERT_EQ(window.voidMask[w], whole.voidMask[o]) << c << "," << row;
    }
  }
  EXPECT_DOUBLE_EQ(window.geo.originX, whole.geo.originX + 70 * 30);
  EXPECT_DOUBLE_EQ(window.geo.originY, whole.geo.originY - 30 * 30);
  EXPECT_THROW(source.read(250, 0, 100, 10), std::invalid_argument);
}

TEST_F(GdalDem, SubdatasetsAreNamed) {
  // A GeoTIFF with two pages is not a subdataset container; NetCDF is, but
  // writing one needs a multidimensional API. A GTiff "GTIFF_DIR:" path
  // shows that such GDAL names open like files.
  test::GdalRaster r = utm(4, 4);
  const std::string p = write("pages.tif", r);
  const Heightfield f = loadDem("GTIFF_DIR:1:" + p, warnings_.options());
  EXPECT_EQ(f.at(2, 1), 12.0f);
}

TEST_F(GdalDem, StripsThatShareBytesAreRefusedBeforeAllocating) {
  // The adversarial case: 370 kB claiming 46340^2 texels took 10.6 GB. Here
  // 2048^2 (16 MB of floats) from 40 kB; the check is the same.
  const std::string p = path("shared.tif");
  test::writeBytes(p, test::sharedStripTiff(2048, 2048));
  test::expectMessage(test::inputErrorOf([&] { DemSource(p, warnings_.options()); }),
                      {p, "its blocks claim 16777216 bytes in all, more than the file's"});
}

TEST_F(GdalDem, StripPastTheEndIsRefusedBeforeAllocating) {
  const std::string p = path("past.tif");
  const auto inOrder = [](uint32_t row, uint32_t data) { return data + 256u * row; };
  test::writeBytes(p, test::stripTiff(64, 64, 64, [&](uint32_t row, uint32_t data) {
                     return row == 5 ? 1000000u : inOrder(row, data);
                   }));
  test::expectMessage(test::inputErrorOf([&] { DemSource(p, warnings_.options()); }),
                      {p, "truncated or corrupt: block 0, 5 lies at bytes 1000000 to 1000256"});
  // Every strip in its own place: a DEM.
  const std::string good = path("good.tif");
  test::writeBytes(good, test::stripTiff(64, 64, 64, inOrder));
  EXPECT_EQ(loadDem(good, warnings_.options()).width, 64);
}

TEST_F(GdalDem, UncompressedStripsShorterThanTheirRowsAreRefused) {
  // 512 rows of 2 kB declared, 16 bytes stored each: no codec, no way.
  const std::string p = path("short.tif");
  test::writeBytes(
      p, test::stripTiff(
             512, 512, 4, [](uint32_t row, uint32_t data) { return data + 16u * row; }, 16));
  test::expectMessage(test::inputErrorOf([&] { DemSource(p, warnings_.options()); }),
                      {p,
                       "declares 1048576 bytes of samples, but its uncompressed blocks of 8192 "
                       "bytes only 8192 bytes can hold"});
}

TEST_F(GdalDem, PngClaimingMoreThanZlibCanHoldIsRefused) {
  const std::string p = path("claims.png");
  test::writeBytes(p, test::pngClaiming(40000, 40000));
  test::expectMessage(test::inputErrorOf([&] { DemSource(p, warnings_.options()); }),
                      {p, "declares 3200000000 bytes of samples, but at zlib's best ratio"});
}

TEST_F(GdalDem, TruncatedFileIsAnInputError) {
  test::GdalRaster r = utm(512, 512);
  r.creationOptions = {"TILED=YES", "COMPRESS=DEFLATE"};
  const std::string p = write("cut.tif", r);
  std::string bytes;
  {
    std::ifstream in(p, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  test::writeBytes(p, bytes.substr(0, bytes.size() / 2));
  test::expectMessage(test::inputErrorOf([&] { loadDem(p); }), {p});
}

}  // namespace
}  // namespace aal
