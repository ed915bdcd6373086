// The body of obscurance.frag and obscurance_paged.frag (the variants: see
// terrain_textures.glsl), and with AAL_OBSCURANCE_TEMPORAL of
// obscurance_temporal.frag and obscurance_temporal_paged.frag. Obscurance
// pass (docs/obscurance.md): containment-test O and W of the surface point
// seen in each pixel, with the pixel's sample set of the 4x4 interleaved
// pattern (Umenhoffer, Tóth, Szirmay-Kalos, "Hardware accelerated ambient
// occlusion...", §4.2; obscuranceCellSampleOffsets).
//
// Temporal reuse (the viewer, docs/obscurance.md): the pass also writes the
// means per sample it found and the surface point they belong to. While the
// view moves (frame.historySubset = subset s >= 0) it evaluates only samples
// [s n / K, (s + 1) n / K) of each pixel's set and averages them with what
// the previous frame found for the same surface point (reprojected with the
// previous frame's matrix, accepted when its texel lies within about a pass
// pixel's footprint: a heightfield has one surface point per texel, so a
// disoccluded pixel finds another texel there and starts afresh: no
// ghosting). Up to n samples are kept; a pixel whose point did not move and
// already has all n keeps them as they are. At rest (s = -1) every sample is
// evaluated: exactly the picture without reuse.
#ifndef AAL_OBSCURANCE_PASS_GLSL
#define AAL_OBSCURANCE_PASS_GLSL

#include "frame.glsl"
#include "obscurance.glsl"
#include "palette.glsl"
#include "terrain_textures.glsl"
#include "variant.glsl"

// After the terrain textures (AAL_TERRAIN_TEXTURE_BINDING...).
#define AAL_OBSCURANCE_BINDING AAL_TERRAIN_TEXTURES_END
layout(set = 0, binding = AAL_OBSCURANCE_BINDING, std140) uniform ObscuranceSamples {
  // xyz: unit-radius (X, Y, Z) of eq. 8 of Umenhoffer et al., "Efficient
  // Methods for Ambient Lighting", 2009; set k's sample i at
  // k * AAL_OBSCURANCE_MAX_SAMPLES + i.
  vec4 offsets[AAL_OBSCURANCE_SAMPLE_SETS * AAL_OBSCURANCE_MAX_SAMPLES];
}
samples;
// texel position, -1 for sky; z: the drawn surface's height
layout(set = 0, binding = AAL_OBSCURANCE_BINDING + 1) uniform sampler2D surfaceImage;
// a: view distance (km)
layout(set = 0, binding = AAL_OBSCURANCE_BINDING + 2) uniform sampler2D ambientImage;

// rgb: W (debug-obscurance: O), a: the pixel's view distance (km) for the
// filter's depth test, 0 for sky.
layout(location = 0) in vec2 uv;  // unused: pixels are addressed by gl_FragCoord
layout(location = 0) out vec4 transfer;

// Samples up to the radius away may lie in another tile: each fetch finds
// its own (terrain_textures.glsl).
float obscuranceHeight(vec2 texel) {
  return terrainHeight(texel);
}

// The palette needs a height and a normal: the occluder's height is at hand,
// its normal would cost four more fetches in the loop (which made the pass
// 2.5x slower on lavapipe), so the shaded point's normal stands in.
vec3 obscuranceAlbedo(vec2 texel, float heightM, vec3 normal) {
  if (kAlbedoSource == AAL_ALBEDO_IMAGE) {
    return terrainAlbedo(texel);
  }
  if (kAlbedoSource == AAL_ALBEDO_CONSTANT) return frame.albedoValue;
  return paletteAlbedo(heightM, normal);
}

// Level 0 of the slope texture holds the same central differences.
vec2 obscuranceSlope(vec2 texel, vec2 cellSizeM) {
  return terrainSlopeLod(texel, 0.0).xy;
}

vec3 obscuranceSampleOffset(int set, int i) {
  return samples.offsets[set * AAL_OBSCURANCE_MAX_SAMPLES + i].xyz;
}

#ifdef AAL_OBSCURANCE_TEMPORAL
// The previous frame's means per sample (open, occluders' albedo rgb) and
// points (texel xy, samples behind the means, 0), at its pass pixels.
layout(set = 0, binding = AAL_OBSCURANCE_BINDING + 3) uniform sampler2D historyMeans;
layout(set = 0, binding = AAL_OBSCURANCE_BINDING + 4) uniform sampler2D historyPoints;
layout(location = 1) out vec4 meansOut;
layout(location = 2) out vec4 pointsOut;

// World position (docs/rendering.md frame) of the drawn point above `texel`
// at height `z` (the mesh's: reprojected, a still camera finds its own pixel).
vec3 obscuranceWorld(vec2 texel, float z) {
  vec2 half_ = 0.5 * (frame.demSize - 1.0);
  return vec3((texel.x - half_.x) * frame.cellSizeM.x, (half_.y - texel.y) * frame.cellSizeM.y, z);
}

// The previous frame's means and sample count for the surface point above
// `texel` (drawn at height `z`), seen `distanceM` away; count 0 when it did
// not see that point. `still`: it saw exactly that point.
vec4 historyAt(vec2 texel, float z, float distanceM, int scale, out float samples,
               out bool still) {
  samples = 0.0;
  still = false;
  if (frame.historyValid == 0) return vec4(0.0);
  vec4 clip = frame.previousViewProj * vec4(obscuranceWorld(texel, z), 1.0);
  if (clip.w <= 0.0) return vec4(0.0);
  ivec2 previousExtent = frame.previousExtent;
  vec2 previousPixel = (clip.xy / clip.w * 0.5 + 0.5) * vec2(previousExtent) / float(scale);
  ivec2 p = ivec2(floor(previousPixel));
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, (previousExtent + scale - 1) / scale))) {
    return vec4(0.0);
  }
  vec4 point = texelFetch(historyPoints, p, 0);
  // A pass pixel covers about this many texels at that distance.
  float footprint = distanceM * frame.pixelAngle * float(scale) / min(frame.cellSizeM.x, frame.cellSizeM.y);
  float apart = distance(point.xy, texel);
  if (point.z <= 0.0 || apart > max(0.75, 1.5 * footprint)) return vec4(0.0);
  samples = point.z;
  still = apart < 1e-3;
  return texelFetch(historyMeans, p, 0);
}
#endif

void main() {
  // At half resolution each pass pixel takes the surface point of the first
  // image pixel of its 2x2 block.
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  int scale = frame.obscurancePixelSize;
  ivec2 source = min(pixel * scale, frame.extent - 1);
  vec3 surface = texelFetch(surfaceImage, source, 0).xyz;
  vec2 texel = surface.xy;
  float distanceKm = texelFetch(ambientImage, source, 0).a;
  if (texel.x < 0.0) {
    transfer = vec4(1.0, 1.0, 1.0, 0.0);
#ifdef AAL_OBSCURANCE_TEMPORAL
    meansOut = vec4(0.0);
    pointsOut = vec4(-1.0, -1.0, 0.0, 0.0);
#endif
    return;
  }
  // One set everywhere: set 0, the unshifted base set.
  int set = frame.obscuranceInterleaved != 0 ? interleavePatternIndex(pixel) : 0;
  int n = frame.obscuranceSamples;
#ifdef AAL_OBSCURANCE_TEMPORAL
  int first = 0, count = n;
  float samples = 0.0;
  bool still = false;
  vec4 history = vec4(0.0);
  if (frame.historySubset >= 0) {
    history = historyAt(texel, surface.z, distanceKm * 1e3, scale, samples, still);
    count = n / AAL_OBSCURANCE_SUBSETS;
    first = frame.historySubset * count;
    if (still && samples >= float(n)) count = 0;  // complete: kept as it is
  }
  vec4 sums = obscuranceSums(texel, frame.cellSizeM, set, first, count, frame.obscuranceRadiusM,
                             frame.obscuranceSteps, 0.0);
  float total = samples + float(count);
  vec4 means = (history * samples + sums) / total;
  meansOut = means;
  pointsOut = vec4(texel, min(total, float(n)), 0.0);
  vec4 e = obscuranceFromMeans(means);
#else
  vec4 e = estimateObscurance(texel, frame.cellSizeM, set, n, frame.obscuranceRadiusM,
                              frame.obscuranceSteps, 0.0);
#endif
  transfer = vec4(kShadingMode == AAL_MODE_DEBUG_OBSCURANCE ? vec3(e.a) : e.rgb, distanceKm);
}

#endif
