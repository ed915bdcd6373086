#version 460
// terrain_gbuffer.frag for scenes of several texture pages
// (terrain_textures.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_GBUFFER
#define AAL_TERRAIN_PAGED
#include "terrain_shading.glsl"
