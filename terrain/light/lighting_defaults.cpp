#include "aperture/terrain/light/lighting_defaults.h"

#include <algorithm>

#include <glm/geometric.hpp>

#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/view/camera.h"

namespace aal {

GeoPlace defaultSunPlace(const Heightfield& field) {
  if (!field.geo.hasCenter) return {};
  return {field.geo.centerLatDeg, field.geo.centerLonDeg};
}

double defaultVisibilityM(const Heightfield& field) {
  return std::max(200e3, 20 * glm::length(demExtentM(field)));
}

float clearDayExposure(double turbidity) {
  Lighting reference;
  setSunAndSky(reference, 180.0, 60.0, turbidity);
  return autoExposure(reference.sunIrradiance, 60.0, reference.skyRadiance);
}

Lighting defaultLighting(const Heightfield& field, double sunAzimuthDeg, double sunElevationDeg,
                         double turbidity, double sunDistanceAu) {
  Lighting l;
  setSunAndSky(l, sunAzimuthDeg, sunElevationDeg, turbidity, sunDistanceAu);
  l.hazeDensityPerM = static_cast<float>(hazeDensityForVisibility(defaultVisibilityM(field)));
  l.exposure = clearDayExposure(turbidity);
  return l;
}

}  // namespace aal
