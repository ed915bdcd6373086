// CPU ray tracer over the heightfield: the ground truth the GPU's shading modes
// are measured against (docs/design.md §9, docs/comparison.md). Slow and simple
// on purpose.
//
// Same scene as the GPU renderer: the camera of camera.h, the terrain as the
// bilinear surface through the texel centres with the centre row's cell size
// (as engine/terrain_scene uploads it), the shading normal from central
// differences one texel apart (as shaders/terrain_shading.glsl), the sun, the average
// sky radiance and the aerial perspective of the same Lighting.
// What differs is the light transport, computed without approximation:
// - sun: `sunRays` stratified points of the sun's disk, each tested with a
//   shadow ray; direct = a/pi E_sun mean(visible_i max(0, N.L_i));
// - sky: `skyRays` stratified cosine-weighted directions around N; a ray that
//   escapes brings L_sky, one that hits the terrain brings one bounce: the
//   hit point's albedo times its direct sun (one shadow ray to the sun's
//   centre) and its sky light (pi L_sky (1 + N_hit.z) / 2, the open sky of its
//   tangent plane); ambient = a/pi * pi/M * sum of those radiances.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/light/lighting.h"
#include "aperture/terrain/view/camera.h"

namespace aal {

constexpr int kMaxReferenceSubpixels = 16;  // per axis

struct ReferenceSettings {
  Camera camera;
  uint32_t width = 0, height = 0;
  Lighting lighting;       // its exposure is the caller's, for display
  glm::vec3 albedo{0.2f};  // constant ground albedo
  int sunRays = 16;        // shadow rays per pixel towards the sun's disk
  int skyRays = 64;        // hemisphere rays per pixel
  // The pixel's footprint: the mean of subpixels x subpixels point samples
  // on a regular grid over the pixel (1: the point through its centre),
  // which share the pixel's rays (each ceil(rays / subpixels^2)). The GPU's
  // mip levels prefilter what a pixel covers; a point sample aliases it
  // (docs/comparison.md).
  int subpixels = 1;
  bool interreflection = true;  // false: rays that hit the terrain bring no light
  uint32_t seed = 1;
  // Pixels that miss the terrain get lighting.sky (as shaders/sky.frag: below
  // the horizon the horizon's colour); false: they stay black.
  bool skyBackground = false;
};

struct ReferenceImage {
  uint32_t width = 0, height = 0;
  std::vector<glm::vec3> radiance;  // linear, row-major, top row first
  std::vector<uint8_t> terrain;     // 1 where the pixel's ray hit the terrain
};

// Renders the terrain pixels; the others get the background sky (or stay
// black) and terrain = 0 (with subpixels, terrain = 1 where every subpixel's
// ray hits the terrain; a pixel on the silhouette mixes terrain and sky).
// Runs in parallel over rows; `progress` (may be empty) gets the finished
// fraction. Throws std::invalid_argument on a zero size, ray counts < 1 or
// subpixels outside 1..kMaxReferenceSubpixels.
ReferenceImage renderReference(const Heightfield& field, const ReferenceSettings& settings,
                               const std::function<void(double)>& progress = {});

// Outgoing radiance (no haze) of the terrain point `point` (on the surface,
// world metres), with the renderer's sun and sky sampling and `seed`.
glm::vec3 referenceRadianceAt(const Heightfield& field, const ReferenceSettings& settings,
                              const glm::dvec3& point, uint32_t seed);

// Relative RMSE of `test` against `reference` over the pixels where mask is 1:
// sqrt(sum |t - r|^2 / sum |r|^2), RGB summed.
double relativeRmse(const std::vector<glm::vec3>& test, const std::vector<glm::vec3>& reference,
                    const std::vector<uint8_t>& mask);

// The terrain mask without its silhouette: pixels whose 4 neighbours are all
// terrain too (the GPU's triangles and the bilinear surface differ there by
// a pixel).
std::vector<uint8_t> interiorMask(const std::vector<uint8_t>& terrain, uint32_t width,
                                  uint32_t height);

}  // namespace aal
