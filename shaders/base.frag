#version 460
// The solid base's shading (base_shading.glsl), forward.
#extension GL_GOOGLE_include_directive : require

#include "base_shading.glsl"
