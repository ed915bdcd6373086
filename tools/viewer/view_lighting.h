// The viewer's sun and sky controls and how they become the renderer's
// lighting: a date, time of day and place (NOAA sun position) or a direct
// sun azimuth/elevation, the sun's angular radius, turbidity, intensities and
// exposure. Pure data and math, so the panel only edits it.
#pragma once

#include <optional>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/light/lighting.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/units.h"

namespace aal {

struct FrameSettings;

struct ViewLighting {
  bool fromTime = true;  // date/time/place; false: direct azimuth/elevation
  int year = 2024, month = 6, day = 21;
  double hourUtc = 15;  // time of day, hours UTC in [0, 24)
  double latitudeDeg = 45, longitudeDeg = 0;
  double sunAzimuthDeg = kDefaultSunAzimuthDeg, sunElevationDeg = kDefaultSunElevationDeg;
  double sunRadiusDeg = kSunAngularRadiusDeg;
  double turbidity = 2.5;
  float sunIntensity = 1, skyIntensity = 1;  // multipliers of E_sun and L_sky
  float exposureStops = 0;                   // relative to the clear-day exposure
  bool playing = false;                      // time of day runs
  double hoursPerSecond = 1;                 // animation speed
  std::optional<double> waterLevelM;         // water at or below (m): --water-level
};

// Defaults for a DEM: its own place (lighting_defaults.h), midsummer 2024,
// mid-afternoon local solar time.
ViewLighting defaultViewLighting(const Heightfield& field);

// The UTC instant of the date and hour (the day is clamped to the month).
UtcTime viewTime(const ViewLighting& lighting);

// Where the controls put the sun: the NOAA position of the date, time and
// place, or the direct azimuth and elevation.
SolarPosition viewSun(const ViewLighting& lighting);

// The lighting of the controls for `field` (lighting_defaults.h
// defaultLighting with the controls' sun radius, the intensity multipliers
// and the exposure stops applied).
Lighting viewLighting(const ViewLighting& lighting, const Heightfield& field);

// Advances the time of day by dtSeconds of animation, wrapping within the
// day, when playing.
void advanceViewTime(ViewLighting& lighting, double dtSeconds);

// Writes the lighting and the water level of the controls into `settings`.
void applyViewLighting(const ViewLighting& lighting, const Heightfield& field,
                       FrameSettings& settings);

}  // namespace aal
