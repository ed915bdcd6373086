#version 460
// 4x4 filter of the obscurance pass (docs/design.md §6; Umenhoffer et al.,
// "Efficient Methods for Ambient Lighting", 2009, §4.2): the box averages
// the 16 toroidal shifts of the interleaved pattern, skipping neighbours whose view
// distance differs from the centre's by more than
// AAL_OBSCURANCE_DEPTH_TOLERANCE of it (another surface). Runs at the
// obscurance pass's resolution.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(set = 0, binding = 1) uniform sampler2D transferImage;  // rgb W or O, a distance (km)

layout(location = 0) in vec2 uv;         // unused: pixels are addressed by gl_FragCoord
layout(location = 0) out vec4 filtered;  // the same, filtered

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 centre = texelFetch(transferImage, pixel, 0);
  if (centre.a <= 0.0) {  // sky
    filtered = centre;
    return;
  }
  int scale = frame.obscurancePixelSize;
  ivec2 size = (frame.extent + scale - 1) / scale;
  float tolerance = float(AAL_OBSCURANCE_DEPTH_TOLERANCE) * centre.a;
  vec3 sum = vec3(0.0);
  float count = 0.0;
  for (int dy = -2; dy <= 1; ++dy) {
    for (int dx = -2; dx <= 1; ++dx) {
      ivec2 p = pixel + ivec2(dx, dy);
      if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) continue;
      vec4 t = texelFetch(transferImage, p, 0);
      if (t.a > 0.0 && abs(t.a - centre.a) <= tolerance) {
        sum += t.rgb;
        count += 1.0;
      }
    }
  }
  filtered = vec4(sum / count, centre.a);  // the centre always counts
}
