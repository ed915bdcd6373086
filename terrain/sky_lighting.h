// Everything the renderer needs of the sun and the sky for one moment:
// direction, the sun's irradiance through the atmosphere, the clear-sky
// model and its average radiance (docs/design.md §5, §7).
#pragma once

#include <glm/vec3.hpp>

#include "sky_model.h"

namespace aal {

struct SkyLighting {
  double sunAzimuthDeg = 0, sunElevationDeg = 0;  // apparent; azimuth clockwise from north
  glm::vec3 sunDirection{0, 0, 1};                // world frame, unit
  glm::vec3 sunIrradiance{0.0f};                  // E_sun, klx (atmosphere.h)
  glm::vec3 skyRadiance{0.0f};                    // average L_sky, kcd/m^2
  PreethamSky sky;
  double turbidity = 2.5;
};

// Lighting for a sun at (azimuth, elevation); the sky fades to black over
// civil twilight and the sun's beam with the part of its disk above the
// horizon (atmosphere.h, sky_model.h).
SkyLighting makeSkyLighting(double sunAzimuthDeg, double sunElevationDeg, double turbidity,
                            double sunDistanceAu = 1.0);

// Visibility (metres, the distance at which contrast drops to 2%) to the
// extinction coefficient of the aerial-perspective haze: 3.912 / visibility
// (Koschmieder).
double hazeDensityForVisibility(double visibilityM);

}  // namespace aal
