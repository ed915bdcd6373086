#version 460
// Obscurance pass (obscurance_pass.glsl), scenes of one texture page.
#extension GL_GOOGLE_include_directive : require

#include "obscurance_pass.glsl"
