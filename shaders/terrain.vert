#version 460
// Terrain patches of the quadtree LOD (shaders/lod.glsl, terrain/quadtree_lod.h)
// displaced by the height texture (vertex texture fetch), with the CDLOD morph.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#include "lod.glsl"

layout(set = 0, binding = 1) uniform sampler2D heightTexture;
layout(set = 0, binding = 4, std430) readonly buffer Patches { LodPatch patches[]; };

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec2 texelPosition;  // continuous (column, row)

// DESIGN §1: x east from the DEM centre, y north (row 0 is the northern edge).
vec3 worldAt(vec2 texel) {
  float z = textureLod(heightTexture, (texel + 0.5) / frame.dem.xy, 0.0).r;
  vec2 half_ = 0.5 * (frame.dem.xy - 1.0);
  return vec3((texel.x - half_.x) * frame.dem.z, (half_.y - texel.y) * frame.dem.w, z);
}

void main() {
  LodPatch node = patches[gl_InstanceIndex];
  vec2 gridPoint = lodGridPoint(gl_VertexIndex);
  // The morph factor comes from the unmorphed vertex, which neighbouring
  // patches share, so they morph it alike (Strugar 2009, §3.3).
  float distanceM =
      length(worldAt(lodPatchTexel(node, gridPoint, frame.dem.xy)) - frame.cameraPos.xyz);
  float k = lodMorphFactor(distanceM, node.morph.xy);
  vec2 texel = lodPatchTexel(node, lodMorphGridPoint(gridPoint, k), frame.dem.xy);
  worldPosition = worldAt(texel);
  texelPosition = texel;
  gl_Position = frame.viewProj * vec4(worldPosition, 1.0);
}
