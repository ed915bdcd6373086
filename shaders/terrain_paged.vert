#version 460
// Terrain patches of the quadtree LOD (terrain_vertex.glsl), scenes of
// several texture pages (terrain_textures.glsl).
#extension GL_GOOGLE_include_directive : require

#define AAL_TERRAIN_PAGED
#include "terrain_vertex.glsl"
