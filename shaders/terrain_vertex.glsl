// The body of terrain.vert and terrain_paged.vert (the variants: see
// terrain_textures.glsl). Terrain patches of the quadtree LOD (shaders/lod.glsl,
// terrain/quadtree_lod.h) displaced by the height texture (vertex texture
// fetch), with the CDLOD morph. Each vertex finds its own tile
// (terrain_textures.glsl), so a patch may straddle tiles.
#ifndef AAL_TERRAIN_VERTEX_GLSL
#define AAL_TERRAIN_VERTEX_GLSL

#include "frame.glsl"
#include "lod.glsl"
#include "terrain_textures.glsl"

layout(set = 0, binding = AAL_TERRAIN_TEXTURES_END,
       std430) readonly buffer Patches {
  LodPatch patches[];
};

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec2 texelPosition;  // continuous (column, row)

// docs/design.md §1: x east from the DEM centre, y north (row 0 is the northern edge).
// Heights at level of detail `lod` (terrain_textures.glsl).
vec3 worldAt(vec2 texel, float lod) {
  float z = terrainHeightLod(texel, lod);
  vec2 half_ = 0.5 * (frame.demSize - 1.0);
  return vec3((texel.x - half_.x) * frame.cellSizeM.x, (half_.y - texel.y) * frame.cellSizeM.y, z);
}

void main() {
  LodPatch node = patches[gl_InstanceIndex];
  vec2 gridPoint = lodGridPoint(gl_VertexIndex);
  // The morph factor comes from the unmorphed vertex, which neighbouring
  // patches share, so they morph it alike (Strugar 2009, §3.3); from its
  // true height, which lies in its node's box, as the crack-free ranges
  // assume (terrain/quadtree_lod.h).
  float distanceM =
      length(worldAt(lodPatchTexel(node, gridPoint, frame.demSize), 0.0) - frame.cameraPos);
  float k = lodMorphFactor(distanceM, node.morph.xy);
  vec2 texel = lodPatchTexel(node, lodMorphGridPoint(gridPoint, k), frame.demSize);
  // Heights prefiltered to the patch's quads (2^level texels), blending into
  // the next level's as the vertex morphs onto its grid: where two levels
  // meet, the finer one is fully morphed and the coarser not yet, so both
  // read level + 1 there and no crack opens.
  worldPosition = worldAt(texel, node.node.w + k);
  texelPosition = texel;
  gl_Position = frame.viewProj * vec4(worldPosition, 1.0);
}

#endif
