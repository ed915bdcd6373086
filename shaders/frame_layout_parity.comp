#version 460
// Reads every member of the Frame uniform block (frame.glsl) and writes its
// bits, member by member in declaration order, so that the test can check
// that each member sits where its C++ twin writes it
// (tests/engine/frame_layout_test.cpp, engine/frame_uniforms.h).
#extension GL_GOOGLE_include_directive : require

#include "frame.glsl"

layout(local_size_x = 1) in;

layout(set = 0, binding = 1, std430) writeonly buffer Words { int words[]; };

int n = 0;
void put(float v) { words[n++] = floatBitsToInt(v); }
void put(int v) { words[n++] = v; }
void put(vec2 v) { put(v.x); put(v.y); }
void put(vec3 v) { put(v.x); put(v.y); put(v.z); }
void put(vec4 v) { put(v.x); put(v.y); put(v.z); put(v.w); }
void put(ivec2 v) { put(v.x); put(v.y); }
void put(mat4 m) { for (int c = 0; c < 4; ++c) put(m[c]); }

void main() {
  put(frame.viewProj);
  put(frame.invViewProj);
  put(frame.previousViewProj);
  put(frame.cameraPos);
  put(frame.pixelAngle);
  put(frame.sunDirection);
  put(frame.sunRadiusRad);
  put(frame.sunIrradiance);
  put(frame.hazeDensityPerM);
  put(frame.skyRadiance);
  put(frame.exposure);
  put(frame.demSize);
  put(frame.cellSizeM);
  put(frame.minHeightM);
  put(frame.maxHeightM);
  put(frame.waterLevelM);
  put(frame.hasWater);
  put(frame.albedoValue);
  put(frame.backgroundAlpha);
  put(frame.baseAlbedo);
  put(frame.baseBottomM);
  put(frame.extent);
  put(frame.previousExtent);
  put(frame.rawOutput);
  put(frame.historySubset);
  put(frame.historyValid);
  put(frame.obscuranceRadiusM);
  put(frame.obscuranceSamples);
  put(frame.obscuranceSteps);
  put(frame.obscuranceInterleaved);
  put(frame.obscurancePixelSize);
  put(frame.tileCoreSize);
  put(frame.tileCount);
  put(frame.tileImageSize);
  put(frame.tileBorder);
  put(frame.heightLayersPerPage);
  put(frame.apertureLayersPerPage);
  put(frame.albedoLayersPerPage);
  put(frame.footprintScale);
  put(frame.sky.perezA);
  put(frame.sky.perezB);
  put(frame.sky.perezC);
  put(frame.sky.perezD);
  put(frame.sky.perezE);
  put(frame.sky.zenith);
  put(frame.sky.sunDirection);
  put(frame.horizonWeights);
}
