// Which tile of a tiled DEM holds a texel position, and where in the tile's
// image it is: the twin of engine/terrain_tiles.h terrainTileTexel (see there
// for the layout); tests/engine/terrain_tiles_test.cpp, TileLookupParity runs both.
#ifndef AAL_TILE_LOOKUP_GLSL
#define AAL_TILE_LOOKUP_GLSL

#include "config.h"

// grid: core width, height (texels), tiles across, down; image: border,
// layers per page, tile image width, height (texels).
struct TerrainTiles {
  ivec4 grid;
  ivec4 image;
};

struct TerrainTileTexel {
  int page;
  int layer;
  vec2 uv;  // normalised coordinate in the tile's image
};

// `texel`: DEM position (column, row), texel centres at integers. Outside
// the DEM the nearest edge tile answers (its border and the sampler's clamp
// repeat the edge texels).
TerrainTileTexel terrainTileTexel(TerrainTiles t, vec2 texel) {
  vec2 core = vec2(t.grid.xy);
  ivec2 tile = clamp(ivec2(floor(texel / core)), ivec2(0), t.grid.zw - 1);
  vec2 local = texel - vec2(tile * t.grid.xy) + float(t.image.x);
  int index = tile.y * t.grid.z + tile.x;
  TerrainTileTexel r;
  r.page = index / t.image.y;
  r.layer = index % t.image.y;
  r.uv = (local + 0.5) / vec2(t.image.zw);
  return r;
}

#endif
