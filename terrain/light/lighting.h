// The light of a frame, one value shared by the GPU renderer
// (engine/terrain_renderer.h FrameSettings) and the CPU reference
// (reference_renderer.h ReferenceSettings): the sun, the sky, the haze
// between the eye and the terrain, and the exposure (docs/design.md §5, §7).
// sky_lighting.h fills in the sun and the sky for a sun position;
// lighting_defaults.h gives the whole of it for a DEM.
#pragma once

#include <glm/vec3.hpp>

#include "aperture/terrain/light/sky_model.h"
#include "aperture/terrain/units.h"

namespace aal {

struct Lighting {
  glm::vec3 sunDirection{0, 0, 1};  // unit, towards the sun, world frame
  float sunRadiusRad = kSunRadiusRad;
  glm::vec3 sunIrradiance{0.0f};  // E_sun at normal incidence, klx (atmosphere.h)
  glm::vec3 skyRadiance{0.0f};    // average L_sky, kcd/m² (docs/design.md §5)
  PreethamSky sky;                // the sky per direction: the background
  float hazeDensityPerM = 0.0f;   // aerial perspective extinction β, 1/m (0: none)
  float exposure = 1.0f;          // tone_map.h; the reference renderer ignores it

  // Field by field; the sky byte by byte.
  bool operator==(const Lighting& other) const;
};

}  // namespace aal
