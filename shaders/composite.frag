#version 460
// Composite of W added to the HDR target (see composite.glsl).
#extension GL_GOOGLE_include_directive : require

#include "composite.glsl"
