#include "aperture/terrain/light/sky_lighting.h"

#include <stdexcept>

#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/solar_position.h"

namespace aal {

void setSunAndSky(Lighting& l, double sunAzimuthDeg, double sunElevationDeg, double turbidity,
                  double sunDistanceAu) {
  l.sunDirection = sunDirection(sunAzimuthDeg, sunElevationDeg);
  l.sunIrradiance = sunIrradiance(sunElevationDeg, turbidity, sunDistanceAu);
  l.sky = makePreethamSky(l.sunDirection, turbidity);
  l.skyRadiance = averageSkyRadiance(l.sky);
}

double hazeDensityForVisibility(double visibilityM) {
  if (!(visibilityM > 0)) throw std::invalid_argument("visibility must be positive");
  return 3.912 / visibilityM;
}

}  // namespace aal
