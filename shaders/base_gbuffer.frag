#version 460
// The solid base's shading (base_shading.glsl) with the obscurance pass's targets.
#extension GL_GOOGLE_include_directive : require

#define AAL_BASE_GBUFFER
#include "base_shading.glsl"
