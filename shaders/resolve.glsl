// Temporal accumulation, the body of resolve.frag and resolve_linear.frag
// (docs/rendering.md, "Temporal reconstruction";
// Karis, "High Quality Temporal Supersampling", SIGGRAPH 2014; Yang et al.,
// "A Survey of Temporal Antialiasing Techniques", 2020). Each frame is drawn
// with its samples shifted by a sub-pixel jitter (a Halton sequence), so
// that over a few frames they cover the output pixels; this pass takes the
// output pixel's value in the drawn picture, reprojects the pixel into the
// last accumulated frame with the camera's motion and the drawn depth,
// clamps what it finds there into the range of the drawn neighbours (a
// value outside it belongs to a surface that is no longer there) and blends
// the two. (Accumulating, a camera that moves is not jittered: its motion
// moves the points.) Two uses:
// - resolve.frag: dynamic resolution, the full-resolution picture rebuilt
//   from frames drawn smaller, in display values; it writes the output and,
//   at higher precision, the history the next frame reads;
// - resolve_linear.frag (AAL_RESOLVE_LINEAR): antialiasing at full
//   resolution in linear radiance (aal-render's image sequences), each
//   pixel the mean of its points over the frames; it writes the history,
//   which the frame then shows.
#include "frame.glsl"

layout(set = 0, binding = 1) uniform sampler2D drawn;       // linear filter
layout(set = 0, binding = 2) uniform sampler2D drawnDepth;  // the drawn frame's depth
layout(set = 0, binding = 3) uniform sampler2D history;     // the last accumulated frame, linear

layout(push_constant) uniform Resolve {
  // This frame's clip space without the jitter (x, y of the output pixel,
  // the drawn depth) to the last accumulated frame's clip space.
  mat4 reproject;
  vec2 jitter;            // drawn pixels: where the samples lie off the pixels' centres
  float currentWeight;    // of this frame's value against the history
  int historyValid;       // 0: no history (the first frame in motion, another scene)
  // How fast a sample's weight falls with its distance from the output
  // pixel's centre (output pixels): 1 / (1 + centreFalloff d²).
  float centreFalloff;
}
resolve;

layout(location = 0) in vec2 uv;  // over the output
#ifdef AAL_RESOLVE_LINEAR
layout(location = 0) out vec4 kept;  // the accumulated frame (the history)
#else
layout(location = 0) out vec4 color;
layout(location = 1) out vec4 kept;  // the same, into the history
#endif

// The history at `at` (texture coordinates) through a Catmull-Rom spline
// in x and y: a bilinear fetch of the last frame blurs it a little at
// every reprojection by a fraction of a pixel, and over the frames a
// history would carry that blur; the spline keeps it sharp. Its 4 x 4 taps
// are 3 x 3 bilinear fetches: the middle two weights of each axis, both
// positive, are one fetch between their texels.
vec4 historyCatmullRom(vec2 at) {
  vec2 size = vec2(textureSize(history, 0));
  vec2 p = at * size;
  vec2 centre = floor(p - 0.5) + 0.5;  // the texel centre at or before p
  vec2 f = p - centre;
  vec2 w0 = f * (-0.5 + f * (1.0 - 0.5 * f));
  vec2 w1 = 1.0 + f * f * (-2.5 + 1.5 * f);
  vec2 w2 = f * (0.5 + f * (2.0 - 1.5 * f));
  vec2 w3 = f * f * (-0.5 + 0.5 * f);
  vec2 w12 = w1 + w2;
  vec2 taps[3] = vec2[3]((centre - 1.0) / size, (centre + w2 / w12) / size, (centre + 2.0) / size);
  vec2 weights[3] = vec2[3](w0, w12, w3);
  vec4 sum = vec4(0.0);
  float total = 0.0;
  for (int j = 0; j < 3; ++j) {
    for (int i = 0; i < 3; ++i) {
      float w = weights[i].x * weights[j].y;
      sum += w * textureLod(history, vec2(taps[i].x, taps[j].y), 0.0);
      total += w;
    }
  }
  return sum / total;
}

// The drawn picture's value at a texel, in the values the history
// blends: display values squared, close to linear light (the sRGB curve is
// near a power of 2.2), so that a rebuilt pixel is nearly the mean of its
// samples' light, as a pixel of more points is; the output is the square
// root, the exact inverse. (The exact sRGB curve both ways read 2.29 %
// against 2.30 % on FrameOutputTest's flight, and its pow() calls made
// lavapipe's frame 12-15 ms longer at 1280x720.) Linear radiance as it is.
vec4 drawnValue(vec4 v) {
#ifdef AAL_RESOLVE_LINEAR
  return v;
#else
  vec3 c = clamp(v.rgb, 0.0, 1.0);
  return vec4(c * c, v.a);
#endif
}

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
  vec4 sampled = drawnValue(texelFetch(drawn, texel, 0));
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
        vec4 t = drawnValue(texelFetch(drawn, clamp(texel + step, ivec2(0), last), 0));
        lo = min(lo, t);
        hi = max(hi, t);
      }
      vec4 h = clamp(historyCatmullRom(previousUv), lo, hi);
      float w = resolve.currentWeight / (1.0 + resolve.centreFalloff * dot(offset, offset));
      result = mix(h, sampled, w);
    }
  }
  if (!reprojected) {
#ifdef AAL_RESOLVE_LINEAR
    // No history here: the drawn sample as it is.
    result = sampled;
#else
    // No history here: the smaller picture scaled up.
    vec2 at = clamp(p + resolve.jitter, vec2(0.5), extent - 0.5);
    result = drawnValue(textureLod(drawn, at / size, 0.0));
#endif
  }
#ifndef AAL_RESOLVE_LINEAR
  color = vec4(sqrt(max(result.rgb, 0.0)), result.a);
#endif
  kept = result;
}
