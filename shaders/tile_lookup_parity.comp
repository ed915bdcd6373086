#version 460
// Evaluates the tile lookup of tile_lookup.glsl for a list of texel positions
// so the tests can compare it with the C++ twin
// (tests/engine/terrain_tiles_test.cpp, TileLookupParity).
#extension GL_GOOGLE_include_directive : require

#include "tile_lookup.glsl"

layout(local_size_x = AAL_TILE_PARITY_GROUP_SIZE) in;

layout(set = 0, binding = 0, std430) readonly buffer Layout { TerrainTiles tiles; };
layout(set = 0, binding = 1, std430) readonly buffer Queries { vec2 texels[]; };
// xy: uv, z: page, w: layer.
layout(set = 0, binding = 2, std430) writeonly buffer Answers { vec4 answers[]; };
layout(push_constant) uniform Push { uint count; };

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= count) return;
  TerrainTileTexel t = terrainTileTexel(tiles, texels[i]);
  answers[i] = vec4(t.uv, float(t.page), float(t.layer));
}
