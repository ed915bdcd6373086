// Anisotropic footprint filtering of the DEM's textures: a few bilinear
// probes along the longer axis of a fragment's footprint on the DEM, at the
// level of its width (Feline: McCormack, Perry, Farkas and Jouppi, "Feline:
// Fast Elliptical Lines for Anisotropic Texture Mapping", SIGGRAPH 1999).
// The twin of terrain/view/texel_footprint.h (see there for the contract);
// tests/engine/texel_footprint_parity_test.cpp runs both.
#ifndef AAL_TEXEL_FOOTPRINT_GLSL
#define AAL_TEXEL_FOOTPRINT_GLSL

#include "config.h"

struct FootprintProbes {
  int count;   // probes, 1..AAL_FOOTPRINT_MAX_PROBES
  float lod;   // level of detail of every probe
  vec2 step;   // DEM texels from one probe to the next
};

// `dx`, `dy`: the texel position's change from one pixel to the next across
// and down the screen (dFdx, dFdy of it; take them in uniform control flow).
// `maxProbes`: at most that many, 1..AAL_FOOTPRINT_MAX_PROBES.
FootprintProbes footprintProbes(vec2 dx, vec2 dy, int maxProbes) {
  float lengthX = dot(dx, dx), lengthY = dot(dy, dy);
  vec2 major = lengthX >= lengthY ? dx : dy;
  float majorTexels = sqrt(max(lengthX, lengthY));
  FootprintProbes p = FootprintProbes(1, 0.0, vec2(0.0));
  if (!(majorTexels > 0.0) || isinf(majorTexels) || isnan(majorTexels)) return p;
  float width = abs(dx.x * dy.y - dx.y * dy.x) / majorTexels;
  float ratio = majorTexels / max(width, 1e-30);
  p.count = int(clamp(ceil(ratio - AAL_FOOTPRINT_RATIO_TOLERANCE), 1.0,
                      float(clamp(maxProbes, 1, AAL_FOOTPRINT_MAX_PROBES))));
  float count = float(p.count);
  p.lod = max(0.0, log2(max(width, majorTexels / count)));
  float coarser = exp2(min(floor(p.lod) + 1.0, float(AAL_TERRAIN_MIP_LEVELS - 1)));
  float reach = float(AAL_TERRAIN_TILE_BORDER) - 1.5 * coarser;
  float offset = 0.5 * (count - 1.0) * majorTexels / count;
  p.step = major / count;
  if (offset > reach) p.step *= reach / offset;
  return p;
}

#endif
