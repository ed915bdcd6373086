// Anisotropic footprint filtering of the DEM's textures (docs/rendering.md,
// "Footprint filtering"): a fragment covers on the DEM a parallelogram
// spanned by the screen derivatives of its texel position, long and narrow
// in an oblique view. One trilinear fetch at the level of its longer axis
// (what a GPU's isotropic filter does) averages normals and apertures over
// more terrain than the pixel covers; one at the shorter axis' level
// aliases along the longer one. Instead a few bilinear probes are spread
// along the longer axis at the level of the parallelogram's width, and
// averaged: Feline (McCormack, Perry, Farkas and Jouppi, "Feline: Fast
// Elliptical Lines for Anisotropic Texture Mapping", SIGGRAPH 1999) with a
// box weighting. The CPU twin of shaders/texel_footprint.glsl;
// tests/engine/texel_footprint_parity_test.cpp runs both.
#pragma once

#include <glm/vec2.hpp>

#include "aperture/shaders/config.h"

namespace aal {

// Most probes per fetch: a footprint more anisotropic than this is read at
// a coarser level, so that the probes still leave no gaps between them. A
// frame may ask for fewer (FrameSettings::anisotropy: each probe is a
// trilinear fetch per texture, and on lavapipe fetches are what a fragment
// costs; docs/rendering.md, "Footprint filtering").
constexpr int kMaxFootprintProbes = AAL_FOOTPRINT_MAX_PROBES;
// What a frame takes unless asked: with the slopes' levels as means, 2
// probes meet the accuracy bars against the ray tracer (jacksboro 250/45
// 1.51 %, 250/20 2.79 %, fBm 30 degrees 1.51 %; bars 1.8, 3.3, 1.8) for
// 6-9 % less of a CPU frame than 3 (1.25, 2.44, 1.17 %; docs/rendering.md,
// "Frame cost, and the anisotropy setting").
constexpr int kDefaultFootprintProbes = 2;
// count rounds |L| / W - this up.
constexpr float kFootprintRatioTolerance = AAL_FOOTPRINT_RATIO_TOLERANCE;

struct FootprintProbes {
  int count = 1;         // probes, 1..kMaxFootprintProbes
  float lod = 0;         // level of detail of every probe (0: the DEM's texels)
  glm::vec2 step{0.0f};  // DEM texels from one probe to the next
};

// The probes of a footprint whose texel position changes by `dx` and `dy`
// (DEM texels) from one pixel to the next across and down the screen. The
// longer axis L is the longer of dx and dy, the width W = |dx × dy| / |L|
// (the parallelogram's extent across L). count = ceil(|L| / W - kFootprintRatioTolerance), at most
// `maxProbes` (1..kMaxFootprintProbes; 1: one trilinear fetch at the level
// of L, a GPU's isotropic filter); lod = log2(max(W, |L| / count)), never below 0;
// step = L / count, so the probes sit at the centres of count equal parts
// of L around the fragment (offsets (i - (count - 1) / 2) step). Where the
// outermost probe's bilinear footprint at the coarser of its two levels
// would reach beyond a tile's border from the edge of its core, the step
// shrinks until it does not: each DEM texture is looked up in its tile
// once per fragment, and the probes read that tile's border
// (AAL_TERRAIN_TILE_BORDER, engine/terrain_tiles.h). Zero or non-finite
// derivatives give one probe at level 0. Single precision, as the shader.
FootprintProbes footprintProbes(glm::vec2 dx, glm::vec2 dy, int maxProbes = kMaxFootprintProbes);

}  // namespace aal
