// Where a vertex of a terrain LOD patch lies (shaders/lod.glsl): its grid
// point, morphed (CDLOD, Strugar 2009, §3.3), displaced by the heights of its
// level of detail. Shared by the terrain (terrain_vertex.glsl) and the solid
// base's walls (base_vertex.glsl), whose tops are the terrain's edge vertices
// computed by the same code, so that no pixel opens between them.
#ifndef AAL_PATCH_VERTEX_GLSL
#define AAL_PATCH_VERTEX_GLSL

#include "frame.glsl"
#include "lod.glsl"
#include "terrain_textures.glsl"

layout(set = 0, binding = AAL_TERRAIN_TEXTURES_END,
       std430) readonly buffer Patches {
  LodPatch patches[];
};

// docs/design.md §1: x east from the DEM centre, y north (row 0 is the northern edge).
// Heights at level of detail `lod` (terrain_textures.glsl).
vec3 worldAt(vec2 texel, float lod) {
  float z = terrainHeightLod(texel, lod);
  vec2 half_ = 0.5 * (frame.demSize - 1.0);
  return vec3((texel.x - half_.x) * frame.cellSizeM.x, (half_.y - texel.y) * frame.cellSizeM.y, z);
}

// World position of grid point `gridPoint` of patch `node`; `texel` is its
// continuous texel position (column, row).
vec3 patchVertex(LodPatch node, vec2 gridPoint, out vec2 texel) {
  // The morph factor comes from the unmorphed vertex, which neighbouring
  // patches share, so they morph it alike (Strugar 2009, §3.3); from its
  // true height, which lies in its node's box, as the crack-free ranges
  // assume (terrain/view/quadtree_lod.h).
  float distanceM =
      length(worldAt(lodPatchTexel(node, gridPoint, frame.demSize), 0.0) - frame.cameraPos);
  float k = lodMorphFactor(distanceM, node.morph.xy);
  texel = lodPatchTexel(node, lodMorphGridPoint(gridPoint, k), frame.demSize);
  // Heights prefiltered to the patch's quads (2^level texels), blending into
  // the next level's as the vertex morphs onto its grid: where two levels
  // meet, the finer one is fully morphed and the coarser not yet, so both
  // read level + 1 there and no crack opens.
  return worldAt(texel, node.node.w + k);
}

#endif
