// The slope texture of one page of heights at one mip level: per texel the
// central differences of the level's heights one texel apart (dz/dx east,
// dz/dy north, m/m), clamped at the image's edge. Sampled with the same
// filter as the heights, these equal the differences of filtered heights
// that the terrain's normals used to take with four fetches (a bilinear fetch
// is linear in the texels, and a shift by one texel keeps its weights), for
// one fetch (docs/rendering.md). Each tile is computed from its own image,
// whose levels hold the whole DEM's bit for bit, so slopes match across
// tiles too (the image's outermost texel, which no fetch reaches, aside).
//
// slopes_horizons.comp (AAL_SLOPES_HORIZONS) also writes B and A: the
// means of the horizons (rad) of the pair of stored directions beside the
// sun (engine/terrain_scene.h setHorizons), and the means of their squares
// into the horizon moment texture (R and G): decoded from their codes at
// level 0, at each level above the means of the 2 x 2 texels of the level
// below (linear, so filtered fetches give a footprint's moments;
// terrain/light/horizon_moments.h; the same in every tile that holds the
// level); the horizon mode reads the means in the normal's fetch. Called
// level by level, each after the one below has been written. A re-lay
// spread over frames (engine/horizon_relay.h) writes one channel of a band
// of rows at a time, the other channel of both images kept.
#ifndef AAL_SLOPES_GLSL
#define AAL_SLOPES_GLSL

#include "config.h"
#include "horizon.glsl"

layout(local_size_x = 8, local_size_y = 8, local_size_z = 1) in;

layout(set = 0, binding = 0) uniform sampler2DArray heights;  // the page, every level
#ifdef AAL_SLOPES_HORIZONS
// The page's level (read too: a re-lay keeps the slopes, keepSlopes).
layout(set = 0, binding = 1, rgba16f) uniform image2DArray slopes;
// The codes of rows [rowBegin, rowEnd) of level 0 (R: the first direction,
// G: the second; with one channel written, R: that channel's direction).
layout(set = 0, binding = 2) uniform usampler2DArray horizonCodes;
// The page's level below (finer; read above level 0).
layout(set = 0, binding = 3, rgba16f) uniform readonly image2DArray finer;
// The second moments of the pair's horizons (rad^2): the level, the level below.
// Read too: a re-lay of one channel keeps the other.
layout(set = 0, binding = 4, rg16f) uniform image2DArray secondMoments;
layout(set = 0, binding = 5, rg16f) uniform readonly image2DArray finerSecondMoments;
#else
layout(set = 0, binding = 1, rg16f) uniform writeonly image2DArray slopes;
#endif

layout(push_constant) uniform Level {
  int level;
  float cellSizeXM, cellSizeYM;
  int horizonBits;  // of the codes (8 or 4)
  int keepSlopes;   // 1: R and G hold this level's slopes already (a re-lay)
  int channel;      // the horizons written: 0 B, 1 A, 2 both
  int rowBegin, rowEnd;  // this level's rows written (the dispatch starts at rowBegin)
}
p;

#ifdef AAL_SLOPES_HORIZONS
// A DEM texel's horizons as half floats (packHalf2x16's rounding), which the
// slope image then stores exactly, whatever its own rounding.
vec2 texelHorizons(vec2 horizons) {
  return unpackHalf2x16(packHalf2x16(horizons));
}
// Their second moments: the squares a hair below (1 - 2^-11, under half a
// half-float step), so that one texel's variance reads 0 rather than
// +-rounding, which would widen its shadow's edge
// (horizonMomentSunFraction).
vec2 texelSecondMoments(vec2 storedHorizons) {
  return storedHorizons * storedHorizons * (1.0 - 1.0 / 2048.0);
}
#endif

// The central differences of the level's heights at texel t.
vec2 levelSlope(ivec3 t, ivec2 last) {
  float east = texelFetch(heights, ivec3(min(t.x + 1, last.x), t.y, t.z), p.level).r;
  float west = texelFetch(heights, ivec3(max(t.x - 1, 0), t.y, t.z), p.level).r;
  float north = texelFetch(heights, ivec3(t.x, max(t.y - 1, 0), t.z), p.level).r;  // row - 1
  float south = texelFetch(heights, ivec3(t.x, min(t.y + 1, last.y), t.z), p.level).r;
  float span = 2.0 * exp2(float(p.level));
  return vec2((east - west) / (span * p.cellSizeXM), (north - south) / (span * p.cellSizeYM));
}

void main() {
  ivec3 t = ivec3(gl_GlobalInvocationID) + ivec3(0, p.rowBegin, 0);
  ivec3 size = imageSize(slopes);
  if (any(greaterThanEqual(t, size)) || t.y >= p.rowEnd) return;
  vec2 horizons = vec2(0.0);
#ifndef AAL_SLOPES_HORIZONS
  vec2 slope = levelSlope(t, size.xy - 1);
#else
  vec4 kept = p.keepSlopes != 0 ? imageLoad(slopes, t) : vec4(0.0);
  vec2 slope = p.keepSlopes != 0 ? kept.rg : levelSlope(t, size.xy - 1);
  vec2 squares;
  if (p.level == 0) {
    float maxCode = float((1 << p.horizonBits) - 1);
    uvec2 codes = texelFetch(horizonCodes, t - ivec3(0, p.rowBegin, 0), 0).rg;
    if (p.channel == 1) codes = codes.yx;  // the one direction's codes are in R
    horizons = texelHorizons(vec2(decodeHorizon(float(codes.x) / maxCode, p.horizonBits),
                                  decodeHorizon(float(codes.y) / maxCode, p.horizonBits)));
    squares = texelSecondMoments(horizons);
  } else {
    // The means of the 2 x 2 below, summed in one fixed order.
    ivec3 f = ivec3(2 * t.xy, t.z);
    ivec3 right = ivec3(1, 0, 0), down = ivec3(0, 1, 0);
    horizons = ((imageLoad(finer, f).ba + imageLoad(finer, f + right).ba) +
                (imageLoad(finer, f + down).ba + imageLoad(finer, f + right + down).ba)) *
               0.25;
    squares = ((imageLoad(finerSecondMoments, f).rg +
                imageLoad(finerSecondMoments, f + right).rg) +
               (imageLoad(finerSecondMoments, f + down).rg +
                imageLoad(finerSecondMoments, f + right + down).rg)) *
              0.25;
  }
  if (p.channel != 2) {
    vec2 keptSquares = imageLoad(secondMoments, t).rg;
    if (p.channel == 0) {
      horizons.y = kept.a;
      squares.y = keptSquares.y;
    } else {
      horizons.x = kept.b;
      squares.x = keptSquares.x;
    }
  }
  imageStore(secondMoments, t, vec4(squares, 0.0, 0.0));
#endif
  imageStore(slopes, t, vec4(slope, horizons));
}

#endif
