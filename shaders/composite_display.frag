#version 460
// Composite of W written as display values (see composite.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_COMPOSITE_DISPLAY
#include "composite.glsl"
