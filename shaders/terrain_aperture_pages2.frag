#version 460
// terrain.frag for scenes whose apertures alone take two texture pages
// (terrain_textures.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_APERTURE_PAGES 2
#include "terrain_shading.glsl"
