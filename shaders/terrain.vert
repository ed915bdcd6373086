#version 460
// Terrain patches of the quadtree LOD (terrain_vertex.glsl), scenes of one
// texture page.
#extension GL_GOOGLE_include_directive : require

#include "terrain_vertex.glsl"
