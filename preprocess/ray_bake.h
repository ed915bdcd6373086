// Brute-force reference baker (Oat's recipe): per texel, rays over the
// hemisphere around the surface normal are marched through the heightfield
// with bilinear heights; the escaping fraction gives the visible solid angle
// and the mean escaping direction the bent normal. Slow, simple, obviously
// right: the tests check the sweep against it.
#pragma once

#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/bake_terrain.h"

namespace aal {

// Adds into sums (4 floats per texel, laid out as skySliceTerms) the escaping
// directions and 2 pi * escaping fraction. Rays are stratified in (uniform
// solid angle, azimuth) and jittered with a fixed per-texel seed.
// The sky-view factor is not available from this method (svf must be empty).
void bakeRays(const BakeTerrain& terrain, const BakeOptions& options, float* sums,
              std::vector<float>& svf);

// True when the ray from world point (x, y, z) in unit direction `dir`
// leaves the terrain without passing under it; zMax is the field's tallest
// height (a ray rising above it has escaped). The terrain must be of a whole
// DEM in memory: the ray marches terrain.heights.dem. Exposed for tests.
bool rayEscapes(const BakeTerrain& terrain, const BakeOptions& options, double x, double y,
                double z, const double dir[3], double zMax);

}  // namespace aal
