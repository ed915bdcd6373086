#version 460
// Terrain grid displaced by the height texture (vertex texture fetch).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(set = 0, binding = 1) uniform sampler2D heightTexture;

layout(location = 0) out vec3 worldPosition;
layout(location = 1) out vec2 texelPosition;  // continuous (column, row)

void main() {
  int stride = frame.grid.x + 1;
  vec2 gridPoint = vec2(gl_VertexIndex % stride, gl_VertexIndex / stride);
  vec2 texel = gridPoint / vec2(frame.grid.xy) * (frame.dem.xy - 1.0);
  float z = textureLod(heightTexture, (texel + 0.5) / frame.dem.xy, 0.0).r;
  vec2 half_ = 0.5 * (frame.dem.xy - 1.0);
  // Row 0 is the northern edge: y decreases with the row (DESIGN §1).
  worldPosition = vec3((texel.x - half_.x) * frame.dem.z, (half_.y - texel.y) * frame.dem.w, z);
  texelPosition = texel;
  gl_Position = frame.viewProj * vec4(worldPosition, 1.0);
}
