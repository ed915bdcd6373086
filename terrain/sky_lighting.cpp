#include "sky_lighting.h"

#include <stdexcept>

#include "atmosphere.h"
#include "solar_position.h"

namespace aal {

SkyLighting makeSkyLighting(double sunAzimuthDeg, double sunElevationDeg, double turbidity,
                            double sunDistanceAu) {
  SkyLighting l;
  l.sunAzimuthDeg = sunAzimuthDeg;
  l.sunElevationDeg = sunElevationDeg;
  l.turbidity = turbidity;
  l.sunDirection = sunDirection(sunAzimuthDeg, sunElevationDeg);
  l.sunIrradiance = sunIrradiance(sunElevationDeg, turbidity, sunDistanceAu);
  l.sky = makePreethamSky(l.sunDirection, turbidity);
  l.skyRadiance = averageSkyRadiance(l.sky);
  return l;
}

double hazeDensityForVisibility(double visibilityM) {
  if (!(visibilityM > 0)) throw std::invalid_argument("visibility must be positive");
  return 3.912 / visibilityM;
}

}  // namespace aal
