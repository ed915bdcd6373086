// The shipped DEM (heightmaps/jacksboro_fault_dem.tif): USGS 3" geographic
// WGS84 int16 with GDAL_NODATA -32768. Loads with true metric spacing.
#include <gtest/gtest.h>

#include <filesystem>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/georeference.h"
#include "aperture/tests/terrain/io/dem_test_util.h"

namespace aal {
namespace {

const std::string kJacksboro =
    std::string(AAL_TEST_SOURCE_DIR) + "/heightmaps/jacksboro_fault_dem.tif";
constexpr double kStepDeg = 1.0 / 1200.0;

TEST(Jacksboro, IsSmallEnoughToShip) {
  EXPECT_LT(std::filesystem::file_size(kJacksboro), 5u * 1024 * 1024);
}

TEST(Jacksboro, LoadsAsGeographicWgs84) {
  test::CapturedWarnings warnings;
  const Heightfield f = loadDem(kJacksboro, warnings.options());
  EXPECT_TRUE(warnings.messages.empty()) << ::testing::PrintToString(warnings.messages);
  EXPECT_EQ(f.format, "GeoTIFF");
  EXPECT_EQ(f.width, 403);
  EXPECT_EQ(f.height, 344);
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  EXPECT_EQ(f.geo.epsg, 4326);
  EXPECT_NEAR(f.geo.stepX, kStepDeg, 1e-15);
  // Tie point: north-west corner at 84.41375 W, 36.7329167 N (PixelIsArea).
  EXPECT_NEAR(f.geo.originX, -84.41375 + 0.5 * kStepDeg, 1e-9);
  EXPECT_NEAR(f.geo.originY, 36.73291666666667 - 0.5 * kStepDeg, 1e-9);
  ASSERT_TRUE(f.geo.hasCenter);
  EXPECT_NEAR(f.geo.centerLatDeg, 36.73291666666667 - 172 * kStepDeg, 1e-9);  // 36.5896
  EXPECT_NEAR(f.geo.centerLonDeg, -84.41375 + 201.5 * kStepDeg, 1e-9);        // -84.2458
}

TEST(Jacksboro, HasMetricSpacingForItsLatitude) {
  const Heightfield f = loadDem(kJacksboro);
  // 3" of latitude: ~92.5 m on WGS84 at 36.6 N (92.6 m on a 6371 km sphere).
  EXPECT_NEAR(f.cellSizeYM, 92.47, 0.02);
  // 3" of longitude at the centre latitude, ~74.6 m; rows narrow northwards.
  EXPECT_NEAR(f.cellSizeXM, parallelArcM(f.geo.centerLatDeg, kStepDeg), 1e-9);
  EXPECT_NEAR(f.cellSizeXM, 74.57, 0.02);
  ASSERT_EQ(f.rowCellSizeXM.size(), 344u);
  EXPECT_NEAR(f.rowCellSizeXM.front(), parallelArcM(f.geo.originY, kStepDeg), 1e-9);
  EXPECT_LT(f.rowCellSizeXM.front(), f.rowCellSizeXM.back());
}

TEST(Jacksboro, HeightsArePlausibleMetres) {
  const Heightfield f = loadDem(kJacksboro);
  EXPECT_TRUE(test::allFinite(f));
  const auto [lo, hi] = std::minmax_element(f.z.begin(), f.z.end());
  // Powell Valley to Cumberland Mountain: a few hundred to about a thousand metres.
  EXPECT_GT(*lo, 150.0f);
  EXPECT_LT(*hi, 1300.0f);
  EXPECT_GT(*hi - *lo, 500.0f);
  EXPECT_DOUBLE_EQ(f.zScale, 1.0);
}

}  // namespace
}  // namespace aal
