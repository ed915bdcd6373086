// Upsampling and composite of W (docs/obscurance.md), the body of
// composite.frag and composite_display.frag. At half resolution each pass
// pixel holds the point of the first image pixel of its 2x2 block: an image
// pixel takes the pass pixels at its own position or, between two, both, of
// those whose view distance is within AAL_OBSCURANCE_DEPTH_TOLERANCE of its
// own (the same surface). The result, ambient x T x W, completes the terrain
// pass's direct x T + in-scattering to (direct + ambient W) T + L_sky (1 - T):
// composite.frag adds it to the HDR target (blending ONE + ONE);
// composite_display.frag (AAL_COMPOSITE_DISPLAY) reads that target, adds it
// and writes the display value, the tone map folded in (one full-screen pass
// fewer).
#ifndef AAL_COMPOSITE_GLSL
#define AAL_COMPOSITE_GLSL

#include "frame.glsl"
#include "tone_map.glsl"
#include "variant.glsl"

layout(set = 0, binding = 1) uniform sampler2D transferImage;  // rgb W or O, a distance (km)
layout(set = 0, binding = 2) uniform sampler2D ambientImage;   // rgb ambient x T, a distance (km)
#ifdef AAL_COMPOSITE_DISPLAY
layout(set = 0, binding = 3) uniform sampler2D hdrImage;  // direct x T + in-scattering, or sky
#endif

layout(location = 0) in vec2 uv;  // unused: pixels are addressed by gl_FragCoord
layout(location = 0) out vec4 color;

// ambient x T x W at `pixel` (0 for sky).
vec3 weightedAmbient(ivec2 pixel) {
  vec4 ambient = texelFetch(ambientImage, pixel, 0);
  if (ambient.a <= 0.0) return vec3(0.0);  // sky
  int scale = frame.obscurancePixelSize;
  ivec2 size = (frame.extent + scale - 1) / scale;
  ivec2 first = pixel / scale;
  // Odd pixels at half resolution lie between two pass pixels.
  ivec2 last = min(first + (pixel - first * scale), size - 1);
  float tolerance = float(AAL_OBSCURANCE_DEPTH_TOLERANCE) * ambient.a;
  // The taps in the order of rows, then columns: each of the 2 x 2 counts
  // once where it is a distinct pass pixel (even pixels: one tap; odd: two
  // or four). Straight-line code with the repeats weighted out, not a loop
  // with bounds that differ from pixel to pixel: llvmpipe runs a loop until
  // its longest lane is done, with the masks and branches that costs
  // (docs/performance.md, "Where a frame's time goes").
  ivec2 taps[4] = ivec2[4](first, ivec2(last.x, first.y), ivec2(first.x, last.y), last);
  bool distinct[4] = bool[4](true, last.x != first.x, last.y != first.y,
                             last.x != first.x && last.y != first.y);
  vec3 sum = vec3(0.0);
  float count = 0.0;
  vec3 nearest = vec3(1.0);  // fallback: the tap closest in depth
  float nearestDifference = 1e30;
  for (int i = 0; i < 4; ++i) {
    vec4 t = texelFetch(transferImage, taps[i], 0);
    float difference = abs(t.a - ambient.a);
    bool counted = distinct[i] && t.a > 0.0;
    bool same = counted && difference <= tolerance;
    sum += same ? t.rgb : vec3(0.0);
    count += same ? 1.0 : 0.0;
    bool closer = counted && !same && difference < nearestDifference;
    nearest = closer ? t.rgb : nearest;
    nearestDifference = closer ? difference : nearestDifference;
  }
  vec3 w = count > 0.0 ? sum / count : nearest;
  return ambient.rgb * w;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 ambient = weightedAmbient(pixel);
#ifdef AAL_COMPOSITE_DISPLAY
  vec4 hdr = texelFetch(hdrImage, pixel, 0);  // alpha: 1 on terrain, the background's on sky
  color = vec4(displayValue(hdr.rgb + ambient, frame.exposure, kRawOutput), hdr.a);
#else
  color = vec4(ambient, 0.0);
#endif
}

#endif
