#version 460
// Dynamic resolution in motion: the full-resolution picture rebuilt from the
// frames drawn smaller (docs/rendering.md, "Temporal reconstruction";
// Karis, "High Quality Temporal Supersampling", SIGGRAPH 2014; Yang et al.,
// "A Survey of Temporal Antialiasing Techniques", 2020). Each frame is drawn
// with its samples shifted by a sub-pixel jitter (a Halton sequence), so
// that over a few frames they cover the output pixels; this pass takes the
// output pixel's value in the drawn picture, reprojects the pixel into the
// last rebuilt frame with the camera's motion and the drawn depth, clamps
// what it finds there into the range of the drawn neighbours (a value
// outside it belongs to a surface that is no longer there) and blends the
// two. It writes the output and, at higher precision, the history the next
// frame reads.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(set = 0, binding = 1) uniform sampler2D drawn;       // display values, linear filter
layout(set = 0, binding = 2) uniform sampler2D drawnDepth;  // the drawn frame's depth
layout(set = 0, binding = 3) uniform sampler2D history;     // the last rebuilt frame, linear

layout(push_constant) uniform Resolve {
  // This frame's clip space without the jitter (x, y of the output pixel,
  // the drawn depth) to the last rebuilt frame's clip space.
  mat4 reproject;
  vec2 jitter;            // drawn pixels: where the samples lie off the pixels' centres
  float currentWeight;    // of this frame's value against the history
  int historyValid;       // 0: no history (the first frame in motion, another scene)
}
resolve;

layout(location = 0) in vec2 uv;  // over the output
layout(location = 0) out vec4 color;
layout(location = 1) out vec4 kept;  // the same, into the history

void main() {
  vec2 extent = vec2(frame.extent);
  vec2 size = vec2(textureSize(drawn, 0));
  ivec2 last = ivec2(extent) - 1;
  // The output pixel's centre, in drawn pixels.
  vec2 p = uv * extent;
  // Drawn texel i holds the scene where, without the jitter, the point
  // i + 0.5 - jitter lies: the texel nearest to p, and how far its sample
  // lies from p in output pixels.
  ivec2 texel = clamp(ivec2(floor(p + resolve.jitter)), ivec2(0), last);
  vec4 sampled = texelFetch(drawn, texel, 0);
  vec2 offset = (vec2(texel) + 0.5 - resolve.jitter - p) * vec2(textureSize(history, 0)) / size;
  vec4 result;
  bool reprojected = false;
  if (resolve.historyValid != 0) {
    float depth = texelFetch(drawnDepth, texel, 0).r;
    vec4 previous = resolve.reproject * vec4(uv * 2.0 - 1.0, depth, 1.0);
    vec2 previousUv = previous.xy / previous.w * 0.5 + 0.5;
    reprojected = previous.w > 0.0 && all(greaterThanEqual(previousUv, vec2(0.0))) &&
                  all(lessThanEqual(previousUv, vec2(1.0)));
    if (reprojected) {
      // The range of the drawn samples around it (the texel and its four
      // neighbours): a history value outside it belongs to a surface that
      // is no longer there.
      vec4 lo = sampled, hi = sampled;
      for (int k = 0; k < 4; ++k) {
        ivec2 step = ivec2(k == 0 ? -1 : k == 1 ? 1 : 0, k == 2 ? -1 : k == 3 ? 1 : 0);
        vec4 t = texelFetch(drawn, clamp(texel + step, ivec2(0), last), 0);
        lo = min(lo, t);
        hi = max(hi, t);
      }
      vec4 h = clamp(textureLod(history, previousUv, 0.0), lo, hi);
      // The sample counts by how near it lies to the pixel's centre (about
      // a quarter of an output pixel wide): over the jitter's cycle each
      // output pixel is given the samples that fall on it.
      float w = resolve.currentWeight / (1.0 + 8.0 * dot(offset, offset));
      result = mix(h, sampled, w);
    }
  }
  if (!reprojected) {
    // No history here: the smaller picture scaled up.
    vec2 at = clamp(p + resolve.jitter, vec2(0.5), extent - 0.5);
    result = textureLod(drawn, at / size, 0.0);
  }
  color = result;
  kept = result;
}
