// The patch of the quadtree LOD (CDLOD, Strugar 2009, "Continuous
// Distance-Dependent Level of Detail for Rendering Heightmaps", JGT 14(4)):
// one fixed grid mesh of kLodPatchQuads x kLodPatchQuads quads that every
// selected quadtree node is drawn with, and the vertex morph that slides a
// patch's vertices onto the next coarser level's grid before the switch.
// The morph functions are the CPU twins of shaders/lod.glsl.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "aperture/shaders/config.h"

namespace aal {

constexpr int kLodPatchQuads = AAL_LOD_PATCH_QUADS;
static_assert(kLodPatchQuads % 2 == 0, "patch quadrants and the morph need an even grid");
// Vertices of the patch: (kLodPatchQuads + 1)^2; vertex i sits at grid point
// (i % (kLodPatchQuads + 1), i / (kLodPatchQuads + 1)) (column, row).
constexpr uint32_t kLodPatchVertices = (kLodPatchQuads + 1) * (kLodPatchQuads + 1);
// Indices of one quadrant of the patch, and of the whole patch.
constexpr uint32_t kLodQuadrantIndices = (kLodPatchQuads / 2) * (kLodPatchQuads / 2) * 6;
constexpr uint32_t kLodPatchIndices = 4 * kLodQuadrantIndices;

// The patch's index buffer: two counter-clockwise triangles per quad (seen
// from above; the diagonal runs north-west to south-east in every quad, so a
// fully morphed 2x2 block of quads collapses onto one coarser quad with the
// same diagonal), laid out quadrant by quadrant (north-west, north-east,
// south-west, south-east) so that quadrant q of a node is drawn with
// firstIndex = q * kLodQuadrantIndices, indexCount = kLodQuadrantIndices.
std::vector<uint32_t> makeLodPatchIndices();

// One drawn patch (an instance), std430 as shaders/lod.glsl reads it.
struct LodPatch {
  // xy: north-west corner of the node (texel column, row); z: quad size
  // (texels, 2^level); w: level (0: finest).
  glm::vec4 node{0.0f};
  // x, y: distance (m) from the camera where the morph to the next coarser
  // level starts and ends (kLodNoMorph for none); zw: 0.
  glm::vec4 morph{0.0f};
};
static_assert(sizeof(LodPatch) == 32, "LodPatch must match the std430 struct of shaders/lod.glsl");

// Morph range of a level that never morphs (the root, or morphing switched
// off for debugging): beyond any distance, finite in single precision.
constexpr float kLodNoMorph = 1e30f;

// Morph factor k in [0, 1] of a vertex `distanceM` from the camera: 0 before
// the morph range, 1 at and beyond its end (Strugar 2009, §3.3 "morph"),
// linear in between. Single precision, as the shader computes it.
float lodMorphFactor(float distanceM, glm::vec2 morphRangeM);

// A patch grid point (integers 0..kLodPatchQuads) moved by morph factor k:
// odd coordinates slide towards the even neighbour below them, so at k = 1
// every vertex sits on a grid point of the next coarser level (Strugar 2009,
// §3.3, eq. "morphVertex"). Even coordinates never move.
glm::vec2 lodMorphGridPoint(glm::vec2 gridPoint, float morphK);

// The texel position (column, row) of a patch grid point of `patch`, clamped
// to the DEM (nodes at the eastern and southern edges reach beyond it; the
// clamp folds their overhang onto the edge).
glm::vec2 lodPatchTexel(const LodPatch& patch, glm::vec2 gridPoint, glm::vec2 demSizeTexels);

}  // namespace aal
