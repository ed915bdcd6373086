// The slope texture of one page of heights at one mip level (dz/dx east,
// dz/dy north, m/m): at level 0 per texel the central differences of the
// DEM's heights one texel apart, clamped at the image's edge; at each level
// above the mean of the 2 x 2 texels below, so a level's texel holds the mean
// slope of the DEM texels it covers and a filtered fetch the mean slope over
// its footprint. The level's own heights' differences, two of its texels
// apart, averaged the slopes over about twice the footprint: the normals of
// far fragments were blurred twice as much as their other textures
// (docs/rendering.md, "Footprint filtering"). Each tile is computed from its
// own image, whose level 0 holds the whole DEM's heights bit for bit, so
// slopes match across tiles too (each level's outermost texel, which holds
// the image's edge and which no fetch reaches, aside).
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
// The page's level below (finer; read above level 0).
layout(set = 0, binding = 3, rg16f) uniform readonly image2DArray finer;
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

// The slope at texel t: at level 0 the central differences of the DEM's
// heights; above, the mean of the 2 x 2 texels of the level below (summed in
// one fixed order), so that every level holds the mean slope of the DEM
// texels it covers, as the other textures' levels hold their means.
vec2 levelSlope(ivec3 t, ivec2 last) {
  if (p.level > 0) {
    ivec3 f = ivec3(2 * t.xy, t.z);
    ivec3 right = ivec3(1, 0, 0), down = ivec3(0, 1, 0);
    return ((imageLoad(finer, f).rg + imageLoad(finer, f + right).rg) +
            (imageLoad(finer, f + down).rg + imageLoad(finer, f + right + down).rg)) *
           0.25;
  }
  float east = texelFetch(heights, ivec3(min(t.x + 1, last.x), t.y, t.z), 0).r;
  float west = texelFetch(heights, ivec3(max(t.x - 1, 0), t.y, t.z), 0).r;
  float north = texelFetch(heights, ivec3(t.x, max(t.y - 1, 0), t.z), 0).r;  // row - 1
  float south = texelFetch(heights, ivec3(t.x, min(t.y + 1, last.y), t.z), 0).r;
  return vec2((east - west) / (2.0 * p.cellSizeXM), (north - south) / (2.0 * p.cellSizeYM));
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
