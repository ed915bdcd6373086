// The viewer's sun and sky controls (tools/viewer/view_lighting.h): no window.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/tools/viewer/view_lighting.h"

namespace aal {
namespace {

Heightfield georeferencedAt(double latDeg, double lonDeg) {
  Heightfield f;
  f.width = f.height = 2;
  f.z.assign(4, 100.0f);
  f.cellSizeXM = f.cellSizeYM = 30;
  f.geo.crs = CrsKind::Geographic;
  f.geo.hasCenter = true;
  f.geo.centerLatDeg = latDeg;
  f.geo.centerLonDeg = lonDeg;
  return f;
}

TEST(ViewLighting, DefaultsToMidAfternoonAtTheDemsPlace) {
  const ViewLighting l = defaultViewLighting(georeferencedAt(36.6, -84.2));
  EXPECT_DOUBLE_EQ(l.latitudeDeg, 36.6);
  EXPECT_DOUBLE_EQ(l.longitudeDeg, -84.2);
  // 15:00 local solar time is 15 + 84.2/15 = 20.61 h UTC.
  EXPECT_NEAR(l.hourUtc, 20.613, 1e-3);
  const SolarPosition sun = viewSun(l);
  EXPECT_GT(sun.azimuthDeg, 230);  // west of south in the afternoon
  EXPECT_LT(sun.azimuthDeg, 290);
  EXPECT_GT(sun.elevationDeg, 30);
}

TEST(ViewLighting, DirectAzimuthAndElevationOverrideTheClock) {
  ViewLighting l;
  l.fromTime = false;
  l.sunAzimuthDeg = 90;
  l.sunElevationDeg = 30;
  const Lighting light = viewLighting(l, georeferencedAt(45, 0));
  EXPECT_NEAR(light.sunDirection.x, std::cos(30 * std::numbers::pi / 180), 1e-5);  // east
  EXPECT_NEAR(light.sunDirection.z, 0.5, 1e-5);
}

TEST(ViewLighting, NeutralControlsLightTheDemLikeAalRender) {
  // aal-render lights a DEM with defaultLighting and the --sun-radius it is
  // given; the viewer's controls at their defaults must give the same.
  ViewLighting l;
  l.fromTime = false;
  l.sunAzimuthDeg = 200;
  l.sunElevationDeg = 30;
  const Heightfield f = georeferencedAt(45, 0);
  Lighting expected = defaultLighting(f, 200, 30, l.turbidity);
  expected.sunRadiusRad = static_cast<float>(l.sunRadiusDeg * std::numbers::pi / 180.0);
  EXPECT_TRUE(viewLighting(l, f) == expected);
  l.exposureStops = 1;
  EXPECT_FALSE(viewLighting(l, f) == expected);
}

TEST(ViewLighting, IntensitiesAndExposureScale) {
  ViewLighting l;
  const Heightfield f = georeferencedAt(45, 0);
  FrameSettings base, scaled;
  applyViewLighting(l, f, base);
  l.sunIntensity = 2;
  l.skyIntensity = 0.5f;
  l.exposureStops = 1;
  applyViewLighting(l, f, scaled);
  const Lighting &a = base.lighting, &b = scaled.lighting;
  EXPECT_NEAR(b.sunIrradiance.y, 2 * a.sunIrradiance.y, 1e-4 * a.sunIrradiance.y);
  EXPECT_NEAR(b.skyRadiance.y, 0.5 * a.skyRadiance.y, 1e-4 * a.skyRadiance.y);
  EXPECT_NEAR(b.exposure, 2 * a.exposure, 1e-6 * a.exposure);
  EXPECT_GT(a.hazeDensityPerM, 0);
  EXPECT_FALSE(base.waterLevelM);  // no water unless asked for
  l.waterLevelM = 350;
  applyViewLighting(l, f, scaled);
  EXPECT_EQ(scaled.waterLevelM, 350.0f);
}

TEST(ViewLighting, PlayingWrapsTheTimeOfDay) {
  ViewLighting l;
  l.hourUtc = 23.5;
  advanceViewTime(l, 10);  // paused: nothing moves
  EXPECT_DOUBLE_EQ(l.hourUtc, 23.5);
  l.playing = true;
  l.hoursPerSecond = 0.25;
  advanceViewTime(l, 4);
  EXPECT_NEAR(l.hourUtc, 0.5, 1e-12);
}

TEST(ViewLighting, DatesOutOfRangeAreClamped) {
  ViewLighting l;
  l.year = 2023;
  l.month = 2;
  l.day = 31;
  l.hourUtc = 12.75;
  const UtcTime t = viewTime(l);
  EXPECT_EQ(t.day, 28);
  EXPECT_EQ(t.hour, 12);
  EXPECT_EQ(t.minute, 45);
  l.year = 2024;
  EXPECT_EQ(viewTime(l).day, 29);
  l.month = 13;
  EXPECT_EQ(viewTime(l).month, 12);
}

}  // namespace
}  // namespace aal
