// Metric spacing on WGS84 against known numbers and GeographicLib's geodesic
// solution (an independent computation), and georeferencing checks.
#include <gtest/gtest.h>

#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include <cmath>
#include <numbers>

#include "aperture/terrain/io/georeference.h"
#include "aperture/tests/terrain/io/dem_test_util.h"

namespace aal {
namespace {

constexpr double kArcSec = 1.0 / 3600.0;

double geodesicM(double lat0, double lon0, double lat1, double lon1) {
  double s = 0;
  GeographicLib::Geodesic::WGS84().Inverse(lat0, lon0, lat1, lon1, s);
  return s;
}

TEST(Georeference, OneArcSecondOfLatitudeIsAbout30Point8Metres) {
  for (double lat : {0.0, 36.6, 45.0, 80.0}) {
    const double m = meridianArcM(lat, lat + kArcSec);
    EXPECT_NEAR(m, geodesicM(lat, 0, lat + kArcSec, 0), 1e-6) << lat;
    // 30.72 m at the equator, 30.87 m at 45 degrees, 31.03 m at the poles.
    EXPECT_NEAR(m, lat <= 45.0 ? 30.8 : 30.95, 0.1) << lat;
  }
}

TEST(Georeference, ThreeArcSecondsOfLongitudeAt36Point6North) {
  const double m = parallelArcM(36.6, 3 * kArcSec);
  // Closed form: N(phi) cos(phi) dLambda, N = a / sqrt(1 - e^2 sin^2 phi).
  const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double phi = 36.6 * std::numbers::pi / 180.0;
  const double expected = a / std::sqrt(1 - e2 * std::sin(phi) * std::sin(phi)) * std::cos(phi) *
                          3 * kArcSec * std::numbers::pi / 180;
  EXPECT_NEAR(m, expected, 1e-9);
  // The geodesic chord between the two points is shorter by far less than a millimetre.
  EXPECT_NEAR(m, geodesicM(36.6, -84.0, 36.6, -84.0 + 3 * kArcSec), 1e-6);
  EXPECT_NEAR(m, 74.5, 0.15);
}

// docs/dem-input.md: longitudes in [-180, 180). A grid from 170 E to 190 E
// (170 W) is centred on the antimeridian, which is -180, not +180.
TEST(Georeference, AntimeridianCentreIsMinus180) {
  GeoReference geo;
  geo.crs = CrsKind::Geographic;
  geo.originX = 170.0;
  geo.originY = 10.0;
  geo.stepX = geo.stepY = 0.1;
  const MetricSpacing s = metricSpacing("g", geo, 201, 11);
  ASSERT_TRUE(s.hasCenter);
  EXPECT_DOUBLE_EQ(s.centerLonDeg, -180.0);
  geo.originX = -190.0;  // the same place a turn to the west
  EXPECT_DOUBLE_EQ(metricSpacing("g", geo, 201, 11).centerLonDeg, -180.0);
  geo.originX = 169.9;  // just west of it stays east
  EXPECT_NEAR(metricSpacing("g", geo, 201, 11).centerLonDeg, 179.9, 1e-9);
}

TEST(Georeference, GeographicGridHasPerRowSpacingAndCentre) {
  GeoReference geo;
  geo.crs = CrsKind::Geographic;
  geo.originX = 10.0;
  geo.originY = 60.0;
  geo.stepX = geo.stepY = 0.01;
  const MetricSpacing s = metricSpacing("g", geo, 201, 101);
  ASSERT_EQ(s.rowCellSizeXM.size(), 101u);
  EXPECT_NEAR(s.rowCellSizeXM[0], geodesicM(60.0, 10.0, 60.0, 10.01), 1e-4);
  EXPECT_NEAR(s.rowCellSizeXM[100], geodesicM(59.0, 10.0, 59.0, 10.01), 1e-4);
  EXPECT_NEAR(s.cellSizeYM, geodesicM(59.0, 10.0, 60.0, 10.0) / 100, 1e-6);
  EXPECT_NEAR(s.cellSizeXM, parallelArcM(59.5, 0.01), 1e-9);
  EXPECT_TRUE(s.hasCenter);
  EXPECT_DOUBLE_EQ(s.centerLatDeg, 59.5);
  EXPECT_DOUBLE_EQ(s.centerLonDeg, 11.0);
}

TEST(Georeference, CentreLongitudeIsNormalised) {
  GeoReference geo;
  geo.crs = CrsKind::Geographic;
  geo.originX = 185.0;
  geo.originY = 1.0;
  geo.stepX = geo.stepY = 1.0;
  EXPECT_NEAR(metricSpacing("g", geo, 11, 3).centerLonDeg, -170.0, 1e-12);
}

TEST(Georeference, RowOnThePoleKeepsAPositiveSpacing) {
  GeoReference geo;
  geo.crs = CrsKind::Geographic;
  geo.originY = 90.0;
  geo.stepX = geo.stepY = 1.0;
  const MetricSpacing s = metricSpacing("g", geo, 4, 3);
  EXPECT_GT(s.rowCellSizeXM[0], 0.0);
  EXPECT_LT(s.rowCellSizeXM[0], 1e-3 + 1e-12);
  EXPECT_TRUE(std::isfinite(s.cellSizeYM));
}

TEST(Georeference, InconsistentGridsAreRefused) {
  GeoReference geo;
  geo.crs = CrsKind::Geographic;
  geo.originY = 10.0;
  geo.stepX = geo.stepY = 1.0;
  test::expectMessage(test::inputErrorOf([&] { metricSpacing("a.tif", geo, 400, 3); }),
                      {"a.tif: inconsistent georeferencing", "more than 360"});
  test::expectMessage(test::inputErrorOf([&] { metricSpacing("a.tif", geo, 4, 120); }),
                      {"beyond +-90"});
  geo.stepY = -1.0;
  test::expectMessage(test::inputErrorOf([&] { metricSpacing("a.tif", geo, 4, 3); }),
                      {"not positive and finite"});
  geo.crs = CrsKind::Projected;
  geo.stepY = 1e-9;
  test::expectMessage(test::inputErrorOf([&] { metricSpacing("a.tif", geo, 4, 3); }),
                      {"cell size in y", "outside"});
}

TEST(Georeference, UtmAndUpsCentresAgreeWithGeographicLib) {
  // PROJ (through OGR) against GeographicLib's own UTM/UPS inverse.
  struct Case {
    int epsg, zone;
    bool north;
    double x, y;
  };
  for (const Case& c :
       {Case{32616, 16, true, 741000.0, 4053000.0}, Case{32734, 34, false, 400000.0, 7000000.0},
        Case{32661, 0, true, 2000000.0, 1500000.0}, Case{25832, 32, true, 500000.0, 5500000.0}}) {
    GeoReference geo;
    geo.crs = CrsKind::Projected;
    geo.epsg = c.epsg;
    geo.stepX = geo.stepY = 30.0;
    geo.originX = c.x - 30.0;  // a 3 x 3 grid centred on (x, y)
    geo.originY = c.y + 30.0;
    const MetricSpacing s = metricSpacing("u.tif", geo, 3, 3);
    double lat = 0, lon = 0;
    GeographicLib::UTMUPS::Reverse(c.zone, c.north, c.x, c.y, lat, lon);
    ASSERT_TRUE(s.hasCenter) << c.epsg;
    EXPECT_NEAR(s.centerLatDeg, lat, 1e-7) << c.epsg;
    EXPECT_NEAR(s.centerLonDeg, lon, 1e-7) << c.epsg;
    EXPECT_DOUBLE_EQ(s.cellSizeXM, 30.0) << "UTM's scale stays within 0.1 %";
    EXPECT_TRUE(s.scaleNote.empty());
  }
}

TEST(Georeference, LocalCrsHasNoCentre) {
  GeoReference geo;
  geo.crs = CrsKind::Projected;  // no WKT, no code: a grid in metres
  geo.stepX = geo.stepY = 2.0;
  const MetricSpacing s = metricSpacing("l.asc", geo, 3, 3);
  EXPECT_FALSE(s.hasCenter);
  EXPECT_DOUBLE_EQ(s.cellSizeYM, 2.0);
}

}  // namespace
}  // namespace aal
