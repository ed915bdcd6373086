#version 460
// Terrain shading, forward: the radiance (see terrain_shading.glsl).
#extension GL_GOOGLE_include_directive : require

#include "terrain_shading.glsl"
