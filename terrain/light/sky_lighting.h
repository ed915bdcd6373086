// The sun and the sky for one moment: the sun's direction and its irradiance
// through the atmosphere, the clear-sky model and its average radiance
// (docs/design.md §5, §7).
#pragma once

#include "aperture/terrain/light/lighting.h"

namespace aal {

// Sets the sun and the sky of `lighting` (sunDirection, sunIrradiance,
// skyRadiance, sky) for a sun at (azimuth clockwise from north, apparent
// elevation): the sky fades to black over civil twilight and the sun's beam
// with the part of its disk above the horizon (atmosphere.h, sky_model.h).
// The sun's radius, the haze and the exposure stay as they are.
void setSunAndSky(Lighting& lighting, double sunAzimuthDeg, double sunElevationDeg,
                  double turbidity, double sunDistanceAu = 1.0);

// Visibility (metres, the distance at which contrast drops to 2%) to the
// extinction coefficient of the aerial-perspective haze: 3.912 / visibility
// (Koschmieder).
double hazeDensityForVisibility(double visibilityM);

}  // namespace aal
