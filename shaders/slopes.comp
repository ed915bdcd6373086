#version 460
// The slope texture of one page of heights at one mip level: per texel the
// central differences of the level's heights one texel apart (dz/dx east,
// dz/dy north, m/m), clamped at the image's edge. Sampled with the same
// filter as the heights, these equal the differences of filtered heights
// that the terrain's normals used to take with four fetches (a bilinear fetch
// is linear in the texels, and a shift by one texel keeps its weights), for
// one fetch (docs/rendering.md). Each tile is computed from its own image,
// whose levels hold the whole DEM's bit for bit, so slopes match across
// tiles too (the image's outermost texel, which no fetch reaches, aside).
#extension GL_GOOGLE_include_directive : require

#include "config.h"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = 0, binding = 0) uniform sampler2DArray heights;            // the page, every level
layout(set = 0, binding = 1, rg16f) uniform writeonly image2DArray slopes;  // the page's level

layout(push_constant) uniform Level {
  int level;
  float cellSizeXM, cellSizeYM;
}
p;

void main() {
  ivec3 t = ivec3(gl_GlobalInvocationID);
  ivec3 size = imageSize(slopes);
  if (any(greaterThanEqual(t, size))) return;
  ivec2 last = size.xy - 1;
  float east = texelFetch(heights, ivec3(min(t.x + 1, last.x), t.y, t.z), p.level).r;
  float west = texelFetch(heights, ivec3(max(t.x - 1, 0), t.y, t.z), p.level).r;
  float north = texelFetch(heights, ivec3(t.x, max(t.y - 1, 0), t.z), p.level).r;  // row - 1
  float south = texelFetch(heights, ivec3(t.x, min(t.y + 1, last.y), t.z), p.level).r;
  float span = 2.0 * exp2(float(p.level));
  imageStore(slopes, t,
             vec4((east - west) / (span * p.cellSizeXM), (north - south) / (span * p.cellSizeYM), 0, 0));
}
