// The body of obscurance.frag and obscurance_paged.frag (the variants: see
// terrain_textures.glsl). Obscurance pass (DESIGN §6): containment-test O and
// W of the surface point seen in each pixel, with the pixel's sample set of
// the 4x4 interleaved pattern (seed 000 §4.2; obscuranceCellSampleOffsets).
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
  // xyz: unit-radius (X, Y, Z) of seed 000 eq. 8; set k's sample i at
  // k * AAL_OBSCURANCE_MAX_SAMPLES + i.
  vec4 offsets[AAL_OBSCURANCE_SAMPLE_SETS * AAL_OBSCURANCE_MAX_SAMPLES];
}
samples;
// texel position, -1 for sky
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
  if (kAlbedoSource == AAL_ALBEDO_CONSTANT) return frame.albedoValue.rgb;
  return paletteAlbedo(heightM, normal);
}

vec3 obscuranceSampleOffset(int set, int i) {
  return samples.offsets[set * AAL_OBSCURANCE_MAX_SAMPLES + i].xyz;
}

void main() {
  // At half resolution each pass pixel takes the surface point of the first
  // image pixel of its 2x2 block.
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  ivec2 source = min(pixel * frame.obscurancePass.z, frame.extent.xy - 1);
  vec2 texel = texelFetch(surfaceImage, source, 0).xy;
  float distanceKm = texelFetch(ambientImage, source, 0).a;
  if (texel.x < 0.0) {
    transfer = vec4(1.0, 1.0, 1.0, 0.0);
    return;
  }
  // One set everywhere: set 0, the unshifted base set.
  int set = frame.obscurancePass.y != 0 ? interleavePatternIndex(pixel) : 0;
  vec4 e = estimateObscurance(texel, frame.dem.zw, set, int(frame.obscurance.y), frame.obscurance.x,
                              int(frame.obscurance.z), 0.0);
  transfer = vec4(kShadingMode == AAL_MODE_DEBUG_OBSCURANCE ? vec3(e.a) : e.rgb, distanceKm);
}

#endif
