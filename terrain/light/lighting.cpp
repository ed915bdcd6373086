#include "aperture/terrain/light/lighting.h"

#include <cstring>

namespace aal {

bool Lighting::operator==(const Lighting& o) const {
  return sunDirection == o.sunDirection && sunRadiusRad == o.sunRadiusRad &&
         sunIrradiance == o.sunIrradiance && skyRadiance == o.skyRadiance &&
         std::memcmp(&sky, &o.sky, sizeof sky) == 0 && hazeDensityPerM == o.hazeDensityPerM &&
         exposure == o.exposure;
}

}  // namespace aal
