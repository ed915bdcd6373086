#include "aperture/tools/options/sun_options.h"

#include <cstdio>

#include "aperture/tools/tool_options.h"

namespace aal {

namespace {

std::string degreesText(double deg) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", deg);
  return text;
}

}  // namespace

void addSunOptions(CLI::App& app, SunOptions& sun, const SunOptionsUse& use) {
  const auto byDefault = [&](double deg) {
    return use.defaultSun ? " (default " + degreesText(deg) + ", as gdaldem)"
                          : std::string(" (default: the sun at the panel's date and time)");
  };
  app.add_option("--sun-azimuth", sun.azimuthDeg,
                 "sun azimuth, degrees clockwise from north" + byDefault(kDefaultSunAzimuthDeg))
      ->check(CLI::Range(-360.0, 720.0));
  app.add_option("--sun-elevation", sun.elevationDeg,
                 "sun elevation above the horizon, degrees" + byDefault(kDefaultSunElevationDeg))
      ->check(CLI::Range(-90.0, 90.0));
  app.add_option("--time", sun.time,
                 "UTC date and time (ISO 8601) for the sun position seen from --lat, --lon");
  app.add_option(
         "--lat", sun.latitudeDeg,
         "latitude the sun is seen from at " + use.placed + " (default: the DEM's centre, else 45)")
      ->check(CLI::Range(-90.0, 90.0));
  app.add_option("--lon", sun.longitudeDeg,
                 "longitude the sun is seen from at " + use.placed +
                     ", east positive (default: the DEM's centre, else 0)")
      ->check(CLI::Range(-180.0, 180.0));
  if (use.radius) {
    app.add_option("--sun-radius", sun.radiusDeg,
                   "sun angular radius in degrees (larger: softer shadow edges)")
        ->check(CLI::Range(0.01, 20.0))
        ->capture_default_str();
  }
}

SolarPosition directSun(const SunOptions& sun) {
  SolarPosition p;
  p.azimuthDeg = sun.azimuthDeg.value_or(kDefaultSunAzimuthDeg);
  p.elevationDeg = sun.elevationDeg.value_or(kDefaultSunElevationDeg);
  return p;
}

SolarPosition sunOf(const SunOptions& sun, const Heightfield& field) {
  if (sun.time.empty()) return directSun(sun);
  return sunAtTime(sun.time, sun.latitudeDeg, sun.longitudeDeg, field);
}

}  // namespace aal
