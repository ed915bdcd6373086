// The body of terrain.vert and terrain_paged.vert (the variants: see
// terrain_textures.glsl). Terrain patches of the quadtree LOD (shaders/lod.glsl,
// terrain/view/quadtree_lod.h) displaced by the height texture (vertex texture
// fetch), with the CDLOD morph (patch_vertex.glsl). Each vertex finds its own
// tile (terrain_textures.glsl), so a patch may straddle tiles.
#ifndef AAL_TERRAIN_VERTEX_GLSL
#define AAL_TERRAIN_VERTEX_GLSL

#include "patch_vertex.glsl"

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec2 texelPosition;  // continuous (column, row)

void main() {
  vec2 texel;
  worldPosition = patchVertex(patches[gl_InstanceIndex], lodGridPoint(gl_VertexIndex), texel);
  texelPosition = texel;
  gl_Position = frame.viewProj * vec4(worldPosition, 1.0);
}

#endif
