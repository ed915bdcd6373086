#version 460
// Terrain shading for the obscurance pass: direct light, the ambient term and
// the surface point in three targets (see terrain_shading.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_GBUFFER
#include "terrain_shading.glsl"
