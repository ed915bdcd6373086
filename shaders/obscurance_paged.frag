#version 460
// Obscurance pass (obscurance_pass.glsl), scenes of several texture pages
// (terrain_textures.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_PAGED
#include "obscurance_pass.glsl"
