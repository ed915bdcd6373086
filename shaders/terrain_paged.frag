#version 460
// terrain.frag for scenes of several texture pages (terrain_textures.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_PAGED
#include "terrain_shading.glsl"
