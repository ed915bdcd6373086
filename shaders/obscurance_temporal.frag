#version 460
// Obscurance pass with temporal reuse (obscurance_pass.glsl), scenes of one
// texture page.
#extension GL_GOOGLE_include_directive : require

#define AAL_OBSCURANCE_TEMPORAL
#include "obscurance_pass.glsl"
