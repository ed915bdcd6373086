// Containment-test obscurances O and the ambient transfer function W of one
// surface point of a heightfield (docs/design.md §6; Umenhoffer et al.,
// "Efficient Methods for Ambient Lighting", 2009, eq. 6-9, and its short
// version by Tóth et al., 2009, §4; Méndez-Feliu et al., "Real-time
// Obscurances with Color Bleeding", 2006, §3). The GLSL twin is
// shaders/obscurance.glsl (checked for parity on the device by
// tests/engine/obscurance_parity_test.cpp).
//
// Units: positions on the heightfield in continuous texel coordinates
// (column, row; texel centres on integers, row 0 north), heights and the
// radius R in metres, albedo linear RGB in [0, 1]. O is in [0, 1]; W is RGB
// with O <= W <= 1.
#pragma once

#include <functional>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "aperture/terrain/heightfield.h"

namespace aal {

// Containment-test obscurances and the ambient transfer W in the renderer.
struct ObscuranceSettings {
  bool enabled = true;
  float radiusM = 0;  // near-field radius R; 0: defaultObscuranceRadiusM
  // n: 8, 16 or 32 (obscurance_samples.h). 16 keeps the frame within 1.5x of
  // the frame without the passes on lavapipe (docs/performance.md).
  int samples = 16;
  int steps = 1;  // m: test points per ray, 1 or 2
  // 16 toroidal shifts of the set (Cranley-Patterson rotations,
  // obscurance_samples.h) on a 4x4 pixel pattern and a 4x4 box filter
  // (Umenhoffer et al. 2009, §4.2); false: one set everywhere, unfiltered (for
  // comparisons).
  bool interleaved = true;
  // O/W at half the image resolution (one point per 2x2 pixels), filtered and
  // upsampled with the depth test; false: at every pixel.
  bool halfResolution = true;
  // Temporal reuse (the viewer, docs/obscurance.md): None: every frame on its
  // own. Refresh: every sample evaluated, and kept for the next frames.
  // Reuse (while the view moves): a quarter of each pixel's samples
  // evaluated and averaged with the earlier frames' for the same surface
  // points (reprojected; new points start afresh).
  enum class History { None, Refresh, Reuse };
  History history = History::None;
};

// Default R: kDefaultObscuranceRadiusCells cells of the coarser axis (the near
// field must span several cells, or the bilinear surface is flat within it),
// at most the shorter side of the DEM (extent in metres, demExtentM).
constexpr float kDefaultObscuranceRadiusCells = 10.0f;
float defaultObscuranceRadiusM(glm::dvec2 cellSizeM, glm::dvec2 demExtentM);

// Throws InputError unless n is 8/16/32, m is 1/2 and 0 < R <= the shorter
// side of the DEM (extent in metres, demExtentM).
void checkObscuranceSettings(const ObscuranceSettings& settings, glm::dvec2 demExtentM);

// What the estimator reads from the terrain. Heights beyond the DEM are the
// edge's (clamp to edge, like the renderer's sampler).
struct ObscuranceField {
  std::function<float(glm::vec2 texel)> heightAt;      // metres
  std::function<glm::vec3(glm::vec2 texel)> albedoAt;  // linear RGB
  glm::vec2 cellSizeM{1.0f};                           // texel spacing x, y
};

// Bilinear height of `field` at a continuous texel position, clamped to the
// edge: what a linear sampler with texel centres on the grid points returns.
float bilinearHeight(const Heightfield& field, glm::vec2 texel);

// Surface normal from central differences one texel apart (the renderer's
// shading normal, shaders/terrain_shading.glsl).
glm::vec3 obscuranceNormal(const ObscuranceField& field, glm::vec2 texel);

// Tangent frame (T, B) around the unit normal N, rotated by rotationRad about
// N: T starts as normalize((0,1,0) x N) (east on flat ground) and B = N x T.
void obscuranceTangentFrame(glm::vec3 normal, float rotationRad, glm::vec3& tangent,
                            glm::vec3& bitangent);

// Interleaved sampling (Umenhoffer et al. 2009, §4.2; Keller & Heidrich 2001):
// pixel (x, y) uses sample set index bayer4x4(x mod 4, y mod 4) in 0..15
// (obscuranceCellSampleOffsets), so every 4x4 block holds all 16 sets. Set k is
// the base set rotated by interleaveRotationRad(k) = 2π·k/16 about N and
// shifted in elevation and distance (obscurance_samples.h).
int interleavePatternIndex(int x, int y);
float interleaveRotationRad(int index);

struct ObscuranceEstimate {
  float obscurance = 1.0f;   // O = Σ S_i / n
  glm::vec3 transfer{1.0f};  // W = Σ S_i / (n - Σ (1 - S_i) a(p_i)), RGB
};

// Umenhoffer et al. 2009, eq. 9, at the surface point above `texel`: test
// points p_ij = x + (j/m) R (X_i T + Y_i B + Z_i N), j = 1..m, with
// (X_i, Y_i, Z_i) the unit-radius `offsets` (obscuranceSampleOffsets, or an
// interleave cell's obscuranceCellSampleOffsets); S_i = 1 when every p_ij is
// outer (p.z >= h(p.xy), exact for a heightfield), and the albedo a of an
// occluded ray is taken at the projection of its first inner point
// (Umenhoffer et al. 2009, §4). W is 0 when every ray is occluded (0/0 in the
// snow limit).
ObscuranceEstimate estimateObscurance(const ObscuranceField& field,
                                      const std::vector<glm::vec3>& offsets, glm::vec2 texel,
                                      float radiusM, int steps, float rotationRad);

}  // namespace aal
