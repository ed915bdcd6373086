// The sun on a tool's command line (aal-render, aal-relief, aal-view): a
// direct --sun-azimuth and --sun-elevation, or the NOAA position at --time
// seen from --lat, --lon, and the disk's --sun-radius.
#pragma once

#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/units.h"

namespace aal {

struct SunOptions {
  std::optional<double> azimuthDeg, elevationDeg;   // --sun-azimuth, --sun-elevation
  std::string time;                                 // --time (ISO 8601, UTC); empty: none
  std::optional<double> latitudeDeg, longitudeDeg;  // --lat, --lon
  double radiusDeg = kSunAngularRadiusDeg;          // --sun-radius
};

// What the tools do differently with these options.
struct SunOptionsUse {
  // Without --sun-azimuth/--sun-elevation, aal-render and aal-relief light
  // from the default sun (units.h); aal-view from its panel's date and time.
  bool defaultSun = true;
  // The times whose sun --lat and --lon place, named in their help.
  std::string placed = "--time";
  // --sun-radius (aal-view's panel sets the radius instead).
  bool radius = true;
};

// --sun-azimuth, --sun-elevation, --time, --lat, --lon and (use.radius)
// --sun-radius, in that order.
void addSunOptions(CLI::App& app, SunOptions& sun, const SunOptionsUse& use = {});

// The sun of --sun-azimuth and --sun-elevation, each the default sun's when
// not given.
SolarPosition directSun(const SunOptions& sun);

// The sun at --time seen from --lat, --lon (default: the DEM's place), else
// directSun.
SolarPosition sunOf(const SunOptions& sun, const Heightfield& field);

}  // namespace aal
