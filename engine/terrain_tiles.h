// How a DEM's textures are split into tiles when they do not fit one image
// (the device's maxImageDimension2D or maxMemoryAllocationSize, or a smaller
// forced tile size), and the lookup from a DEM texel position to a tile. No
// Vulkan here: the C++ twin of shaders/tile_lookup.glsl
// (tests/engine/terrain_tiles_test.cpp, TileLookupParity runs both).
//
// Every tile owns a core of coreWidth x coreHeight DEM texels (the last tile
// of a row or column owns fewer when the DEM ends) and carries a border of
// `border` texels on each side copied from its neighbours, or clamped to the
// DEM's edge, so a trilinear fetch near a core's edge reads only its own
// tile. Tile images have kTerrainMipLevels levels, and their cores, borders
// and sizes are multiples of kTerrainMipAlignment texels, so a level's
// texels average the same DEM texels in every tile: level l of the whole
// DEM, cut into tiles. A fetch then gives the same value whatever the
// tiling, and a DEM of one tile is laid out the same way (with its border;
// its image rounded up to the alignment). Tiles are layers of 2D array
// images ("pages", one allocation each); tile i is layer i % layersPerPage
// of page i / layersPerPage, rows of tiles from the north-west.
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec2.hpp>

#include "aperture/shaders/config.h"

namespace aal {

// Mip levels of every tile image, and the texels the coarsest level's
// texels span per side.
constexpr uint32_t kTerrainMipLevels = AAL_TERRAIN_MIP_LEVELS;
constexpr uint32_t kTerrainMipAlignment = 1u << (kTerrainMipLevels - 1);
// Border texels per side: the coarsest level's bilinear footprint reaches
// 1.5 of its texels beyond a core's edge.
constexpr uint32_t kTerrainTileBorder = AAL_TERRAIN_TILE_BORDER;
static_assert(kTerrainTileBorder % kTerrainMipAlignment == 0 &&
              2 * kTerrainTileBorder >= 3 * kTerrainMipAlignment + 2);
// Pages per texture kind that the shaders bind.
constexpr uint32_t kTerrainTilePages = AAL_TERRAIN_TILE_PAGES;
// The DEM's textures, in the shaders' binding order (terrain_textures.glsl).
enum class TerrainTexture : int { Height = 0, Aperture = 1, Albedo = 2 };
constexpr int kTerrainTextureKinds = 3;
// Bytes per texel: R32F heights, RGBA16F apertures, RGBA8 albedo. Tiles are
// sized so that one aperture layer with its mip chain fits an allocation;
// each kind then packs as many layers into a page as fit.
constexpr uint64_t kTerrainTextureBytes[kTerrainTextureKinds] = {4, 8, 4};

// What the caller may ask for beyond the device's limits (tests, aal-render
// --max-tile): smaller tiles, and smaller pages (as if the device's
// allocations were at most maxPageBytes).
struct TerrainTiling {
  uint32_t maxTileTexels = 0;  // core texels per side; 0: the device's limits decide
  uint64_t maxPageBytes = 0;   // 0: the device's maxMemoryAllocationSize
};

struct TerrainTileLimits {
  uint32_t maxTileTexels = 0;  // forced core size per side; 0: only the device's limits
  uint32_t maxImageDimension = 16384;
  uint32_t maxArrayLayers = 2048;
  uint64_t maxAllocationBytes = uint64_t{1} << 31;
};

struct TerrainTileLayout {
  uint32_t demWidth = 0, demHeight = 0;
  uint32_t coreWidth = 0, coreHeight = 0;  // DEM texels owned by one tile
  uint32_t tilesX = 1, tilesY = 1;
  uint32_t border = kTerrainTileBorder;
  // Per TerrainTexture: tiles (layers) per page, and pages.
  uint32_t layersPerPage[kTerrainTextureKinds] = {1, 1, 1};
  uint32_t pages[kTerrainTextureKinds] = {1, 1, 1};

  uint32_t tileCount() const { return tilesX * tilesY; }
  // Core and borders, rounded up to the mip alignment.
  uint32_t imageWidth() const { return alignedToMips(coreWidth + 2 * border); }
  uint32_t imageHeight() const { return alignedToMips(coreHeight + 2 * border); }
  static uint32_t alignedToMips(uint32_t texels) {
    return (texels + kTerrainMipAlignment - 1) / kTerrainMipAlignment * kTerrainMipAlignment;
  }
  uint32_t layersPerPageOf(TerrainTexture kind) const { return layersPerPage[int(kind)]; }
  uint32_t pagesOf(TerrainTexture kind) const { return pages[int(kind)]; }
  // Layers in page `page` of `kind` (the last page may hold fewer).
  uint32_t layersIn(TerrainTexture kind, uint32_t page) const;
  // Texels of one tile image with its mip chain.
  uint64_t layerTexels() const;
  // Texels of all tiles of one kind, borders, mip levels and unused overhang included.
  uint64_t texelsPerKind() const { return layerTexels() * tileCount(); }
};

// One tile when the DEM (with its border) fits one image of the device (and
// maxTileTexels) and its apertures one allocation; otherwise tiles of at
// most min(maxTileTexels, maxImageDimension - 2 border) texels across, as
// even as the mip alignment allows, one aperture layer fitting an
// allocation. Throws
// std::runtime_error naming the sizes when a kind would need more than
// kTerrainTilePages pages.
TerrainTileLayout planTerrainTiles(uint32_t demWidth, uint32_t demHeight,
                                   const TerrainTileLimits& limits);

// A DEM texel position's tile: its page and layer in `kind`'s pages, and the
// normalised coordinate in the tile's image of that position (texel centres at integers, as in
// shaders/tile_lookup.glsl). Positions outside the DEM go to the nearest
// edge tile; the sampler's clamp then repeats the edge as the single image's
// clamp would.
struct TerrainTileTexel {
  int page = 0;
  int layer = 0;
  glm::vec2 uv{0.0f};
};
TerrainTileTexel terrainTileTexel(const TerrainTileLayout& layout, TerrainTexture kind,
                                  glm::vec2 texel);

// "W x H texels in X x Y tiles of C x D (+B border) ..." for messages.
std::string describeTerrainTiles(const TerrainTileLayout& layout);

}  // namespace aal
