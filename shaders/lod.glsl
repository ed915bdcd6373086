// Quadtree LOD patches (CDLOD, Strugar 2009, JGT 14(4)): where a patch
// vertex sits and how it morphs onto the next coarser level's grid. The C++
// twins are in terrain/view/lod_patch.h; tests/engine/lod_parity_test.cpp runs
// both.
#ifndef AAL_LOD_GLSL
#define AAL_LOD_GLSL

#include "config.h"

// One drawn patch (terrain/view/lod_patch.h LodPatch, std430).
struct LodPatch {
  vec4 node;   // xy: north-west corner (texel column, row); z: quad size (texels); w: level
  vec4 morph;  // x, y: morph start and end (m from the camera)
};

// Grid point (column, row; integers 0..AAL_LOD_PATCH_QUADS) of patch vertex
// `vertexIndex`.
vec2 lodGridPoint(int vertexIndex) {
  int stride = AAL_LOD_PATCH_QUADS + 1;
  return vec2(vertexIndex % stride, vertexIndex / stride);
}

// 0 before the morph range, 1 at and beyond its end, linear in between.
float lodMorphFactor(float distanceM, vec2 morphRangeM) {
  return clamp((distanceM - morphRangeM.x) / (morphRangeM.y - morphRangeM.x), 0.0, 1.0);
}

// Odd grid coordinates slide towards their even neighbour below, so that at
// k = 1 the vertex sits on the coarser level's grid (Strugar 2009, §3.3).
vec2 lodMorphGridPoint(vec2 gridPoint, float morphK) {
  return gridPoint - fract(gridPoint * 0.5) * 2.0 * morphK;
}

// Texel position (column, row) of a grid point, clamped to the DEM.
vec2 lodPatchTexel(LodPatch node, vec2 gridPoint, vec2 demSizeTexels) {
  return min(node.node.xy + gridPoint * node.node.z, demSizeTexels - 1.0);
}

#endif
