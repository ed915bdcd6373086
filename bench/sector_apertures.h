// Several apertures per texel: Oat's "next level" (Oat,
// Ambient Aperture Lighting, SIGGRAPH 2006 course: multiple visibility
// apertures, and occlusion "anti-apertures"), tried against the directional
// horizons (terrain/io/horizon_map.h) for the sun. docs/comparison.md,
// "Several apertures per texel".
//
// The sky around a texel is cut into K azimuth sectors of 2 pi / K, sector k
// covering azimuths [k, k + 1) * 2 pi / K counter-clockwise from east (the
// bake's convention). Per sector the bake sums the same slice terms as the
// single aperture (sky_slice.h, docs/design.md §3), and summarises them as
// Oat summarises the whole sky: a cap centred on the mean direction with the
// same solid angle.
// - Aperture of sector k: the visible sky of the sector, above
//   theta0 = max(horizon, tangent plane).
// - Anti-aperture of sector k: the occluded sky of the sector above the
//   horizontal, 0 <= theta < theta0, the part where a sun can be hidden.
// The single aperture is the union of the sector apertures (their sums add
// up to its sums), so the sky fill would stay Oat's single cap.
// This is the comparison's CPU code: no shading mode uses it
// (docs/comparison.md says why).
#pragma once

#include <vector>

#include <glm/vec3.hpp>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/heightfield.h"

namespace aal {

// A cap: unit centre and arc length (rad). Radius 0 for an empty region.
struct SectorCap {
  glm::vec3 centre{0, 0, 1};
  float radiusRad = 0;
};

struct SectorApertures {
  int width = 0, height = 0, sectors = 0;
  // sectors caps per texel, row-major from the north-west corner as the
  // aperture map.
  std::vector<SectorCap> apertures;      // visible sky of each sector
  std::vector<SectorCap> antiApertures;  // occluded sky above the horizontal
  std::vector<float> visibleSolidAngle;  // per texel and sector, sr
  std::vector<float> occludedSolidAngle;

  size_t slot(size_t texel, int sector) const { return texel * size_t(sectors) + size_t(sector); }
};

// The sector (0..sectors-1) that holds azimuth phiRad (counter-clockwise
// from east).
int sectorOfAzimuth(double phiRad, int sectors);

// Bakes K = `sectors` apertures and anti-apertures per texel from the
// sweep's horizons of options.azimuths azimuths (options: azimuths, edge,
// curvature, maximum distance; the sweep method only). Azimuths must be a
// multiple of `sectors`, which puts a slice on every sector boundary: it
// adds half its terms to each side. Throws std::invalid_argument for
// sectors outside [1, 16], azimuths not a multiple of them, or options the
// bake refuses.
SectorApertures bakeSectorApertures(const Heightfield& field, const BakeOptions& options,
                                    int sectors);

// How the sun's visible fraction is read from the sector caps.
enum class SectorLookup {
  Containing,  // the cap of the sector that holds the sun's azimuth
  Blended,     // linear in azimuth between the caps of the two nearest sector centres
  Union,       // the largest over all sectors (the sun inside any cap is visible)
};

// The fraction of the sun's disk (unit direction sun, angular radius
// sunRadiusRad) inside texel `texel`'s sector apertures, by the exact cap
// intersection (capIntersectionExact, terrain/light/caps.h).
float sectorApertureSunFraction(const SectorApertures& map, size_t texel, const glm::vec3& sun,
                                float sunRadiusRad, SectorLookup lookup);

// One minus the fraction of the sun's disk inside the anti-apertures.
float antiApertureSunFraction(const SectorApertures& map, size_t texel, const glm::vec3& sun,
                              float sunRadiusRad, SectorLookup lookup);

}  // namespace aal
