#version 460
// Obscurance pass with temporal reuse (obscurance_pass.glsl), scenes of
// several texture pages (terrain_textures.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_PAGED
#define AAL_OBSCURANCE_TEMPORAL
#include "obscurance_pass.glsl"
