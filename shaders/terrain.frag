#version 460
// Terrain shading: ambient aperture lighting (DESIGN §5) plus aerial perspective.
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"
#include "shading.glsl"

layout(set = 0, binding = 1) uniform sampler2D heightTexture;
layout(set = 0, binding = 2) uniform sampler2D apertureTexture;  // rgb bent normal, a arc length
layout(set = 0, binding = 3) uniform sampler2D albedoTexture;

layout(location = 0) in vec3 worldPosition;
layout(location = 1) in vec2 texelPosition;

layout(location = 0) out vec4 color;

float heightAt(vec2 texel) { return textureLod(heightTexture, (texel + 0.5) / frame.dem.xy, 0.0).r; }

// Normal from central differences of the heights, one texel apart.
vec3 surfaceNormal(vec2 texel) {
  float dx = heightAt(texel + vec2(1, 0)) - heightAt(texel - vec2(1, 0));
  float dy = heightAt(texel - vec2(0, 1)) - heightAt(texel + vec2(0, 1));  // north is row - 1
  return normalize(vec3(-dx / (2.0 * frame.dem.z), -dy / (2.0 * frame.dem.w), 1.0));
}

// Procedural ground colour by height and slope when no albedo image is given.
vec3 paletteAlbedo(float z, vec3 normal) {
  float slope = sqrt(max(0.0, 1.0 - normal.z * normal.z)) / max(normal.z, 1e-3);
  vec3 grass = vec3(0.10, 0.16, 0.06);
  vec3 forest = vec3(0.06, 0.10, 0.05);
  vec3 rock = vec3(0.22, 0.20, 0.18);
  vec3 snow = vec3(0.80, 0.82, 0.85);
  float range = max(frame.heights.y - frame.heights.x, 1.0);
  float h = (z - frame.heights.x) / range;
  vec3 a = mix(grass, forest, smoothstep(0.2, 0.6, h));
  a = mix(a, rock, smoothstep(0.5, 1.0, slope));
  a = mix(a, snow, smoothstep(2800.0, 3200.0, z) * (1.0 - smoothstep(0.5, 0.9, slope)));
  if (frame.heights.w > 0.5 && z <= frame.heights.z) a = vec3(0.02, 0.04, 0.06);
  return a;
}

void main() {
  vec2 uv = (texelPosition + 0.5) / frame.dem.xy;
  vec4 aperture = textureLod(apertureTexture, uv, 0.0);
  ShadingInputs s;
  s.normal = surfaceNormal(texelPosition);
  s.bentNormal = normalize(aperture.xyz);
  s.apertureRad = aperture.w;
  s.albedo = frame.grid.w != 0 ? textureLod(albedoTexture, uv, 0.0).rgb
                               : paletteAlbedo(worldPosition.z, s.normal);
  s.sunDirection = frame.sunDirection.xyz;
  s.sunRadiusRad = frame.sunDirection.w;
  s.sunIrradiance = frame.sunIrradiance.rgb;
  s.skyRadiance = frame.skyRadiance.rgb;
  s.transfer = vec3(1.0);
  vec3 radiance = shade(s, frame.grid.z);
  if (frame.display.y < 0.5) {
    // Aerial perspective: light scattered in towards the eye by the haze.
    float distance = length(worldPosition - frame.cameraPos.xyz);
    float transmittance = exp(-frame.skyRadiance.w * distance);
    radiance = radiance * transmittance + frame.skyRadiance.rgb * (1.0 - transmittance);
  }
  color = vec4(radiance, 1.0);
}
