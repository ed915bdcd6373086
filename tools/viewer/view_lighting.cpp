#include "aperture/tools/viewer/view_lighting.h"

#include <algorithm>
#include <cmath>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/terrain/light/lighting_defaults.h"

namespace aal {

namespace {

int daysInMonth(int year, int month) {
  static constexpr int kDays[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
  const bool leap = (year % 4 == 0 && year % 100 != 0) || year % 400 == 0;
  return month == 2 && leap ? 29 : kDays[std::clamp(month, 1, 12) - 1];
}

}  // namespace

ViewLighting defaultViewLighting(const Heightfield& field) {
  ViewLighting l;
  const GeoPlace place = defaultSunPlace(field);
  l.latitudeDeg = place.latitudeDeg;
  l.longitudeDeg = place.longitudeDeg;
  // 15:00 local solar time: 4 minutes of time per degree of longitude.
  l.hourUtc = std::fmod(15.0 - place.longitudeDeg / 15.0 + 48.0, 24.0);
  return l;
}

UtcTime viewTime(const ViewLighting& l) {
  UtcTime t;
  t.year = std::clamp(l.year, 1800, 2100);
  t.month = std::clamp(l.month, 1, 12);
  t.day = std::clamp(l.day, 1, daysInMonth(t.year, t.month));
  const double hour = std::clamp(l.hourUtc, 0.0, 24.0 - 1e-6);
  t.hour = static_cast<int>(hour);
  const double minutes = (hour - t.hour) * 60.0;
  t.minute = std::min(static_cast<int>(minutes), 59);
  t.second = std::clamp((minutes - t.minute) * 60.0, 0.0, 59.999);
  return t;
}

SolarPosition viewSun(const ViewLighting& l) {
  if (l.fromTime) return solarPosition(viewTime(l), l.latitudeDeg, l.longitudeDeg);
  SolarPosition sun;
  sun.azimuthDeg = l.sunAzimuthDeg;
  sun.elevationDeg = l.sunElevationDeg;
  return sun;
}

Lighting viewLighting(const ViewLighting& l, const Heightfield& field) {
  const SolarPosition sun = viewSun(l);
  Lighting light =
      defaultLighting(field, sun.azimuthDeg, sun.elevationDeg, l.turbidity, sun.sunDistanceAu);
  light.sunIrradiance *= l.sunIntensity;
  light.skyRadiance *= l.skyIntensity;
  light.sky.zenith.x *= l.skyIntensity;  // the background sky too
  light.sunRadiusRad = static_cast<float>(radians(l.sunRadiusDeg));
  light.exposure *= std::exp2(l.exposureStops);
  return light;
}

void advanceViewTime(ViewLighting& l, double dtSeconds) {
  if (!l.playing) return;
  l.hourUtc = std::fmod(l.hourUtc + l.hoursPerSecond * dtSeconds, 24.0);
  if (l.hourUtc < 0) l.hourUtc += 24.0;
}

void applyViewLighting(const ViewLighting& l, const Heightfield& field, FrameSettings& s) {
  s.lighting = viewLighting(l, field);
  if (l.waterLevelM) s.waterLevelM = static_cast<float>(*l.waterLevelM);
}

}  // namespace aal
