// What the tools derive from a DEM when the user gives no lighting options:
// the place for the sun position, the distance haze and the exposure. Shared
// by aal-render and aal-view so that both show a DEM the same way.
#pragma once

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/light/lighting.h"

namespace aal {

struct GeoPlace {
  double latitudeDeg = 45, longitudeDeg = 0;
};

// The DEM's own centre when it is georeferenced, else 45°N 0°E (docs/design.md §7).
GeoPlace defaultSunPlace(const Heightfield& field);

// Default haze: a clear day scaled with the DEM so that any size reads with
// depth but is not washed out: visibility 20 DEM diagonals, at least 200 km.
double defaultVisibilityM(const Heightfield& field);

// Exposure fixed by a clear-day sun at 60° elevation (tone_map.h
// autoExposure), so that dusk and night come out darker than noon instead of
// all grey.
float clearDayExposure(double turbidity);

// The lighting of `field` for a sun at (azimuth, elevation) when nothing else
// is asked for: that sun and its sky (sky_lighting.h), the sun's radius at
// 1 AU, the haze of defaultVisibilityM and clearDayExposure.
Lighting defaultLighting(const Heightfield& field, double sunAzimuthDeg, double sunElevationDeg,
                         double turbidity, double sunDistanceAu = 1.0);

}  // namespace aal
