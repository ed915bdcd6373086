#version 460
// The solid base's walls and bottom (base_vertex.glsl), scenes of one texture page.
#extension GL_GOOGLE_include_directive : require

#include "base_vertex.glsl"
