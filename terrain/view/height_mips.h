// The DEM's heights as the renderer's prefiltered levels hold them
// (docs/rendering.md, "Mip levels"): level l has texels of 2^l x 2^l DEM
// texels, each the mean of its block, with the DEM's edge texels repeated
// beyond the edge (what a tile's clamped border holds); a fetch is bilinear
// between the level's texel centres, as the GPU's linear sampler reads it.
// The quadtree LOD (terrain/view/quadtree_lod.h) measures the geometric error of
// its levels with these heights, so the error is the one of the surface the
// vertex shader draws.
#pragma once

#include <vector>

#include "aperture/terrain/heightfield.h"

namespace aal {

// The mean of 2 x 2 texels as every mip level is reduced, here and in the
// renderer's uploads (engine/terrain_scene.cpp): summed in this fixed order
// so that a level is bit for bit the same on the CPU and in every tile.
inline float meanOf2x2(float upperLeft, float upperRight, float lowerLeft, float lowerRight) {
  return ((upperLeft + upperRight) + (lowerLeft + lowerRight)) * 0.25f;
}

class HeightMips {
 public:
  // Levels 0 (the DEM itself) to `levels` - 1. Memory: about a third of the
  // DEM's heights (4/3 B per texel) beyond the field, which must outlive it.
  HeightMips(const Heightfield& field, int levels);

  int levels() const { return static_cast<int>(levels_.size()) + 1; }
  // Height (m) at the DEM texel position (column, row) from level `level`
  // (clamped to the coarsest), bilinear, as terrainHeightLod(texel, level)
  // in shaders/terrain_textures.glsl.
  float at(int level, double column, double row) const;

 private:
  struct Level {
    int width = 0, height = 0;  // texels, one of margin on every side included
    std::vector<float> texels;
    float at(int k, int m) const;  // level texel (k, m), k in [-1, width - 2]
  };
  const Heightfield& field_;
  std::vector<Level> levels_;  // levels 1 and up
};

}  // namespace aal
