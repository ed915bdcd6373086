#version 460
// The solid base's walls and bottom (base_vertex.glsl), scenes whose heights
// span texture pages.
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_PAGED
#include "base_vertex.glsl"
