// How a DEM's textures are split into tiles when they do not fit one image
// (the device's maxImageDimension2D or maxMemoryAllocationSize, or a smaller
// forced tile size), and the lookup from a DEM texel position to a tile. No
// Vulkan here: the C++ twin of shaders/tile_lookup.glsl
// (tests/engine/tile_lookup_parity_test.cpp runs both).
//
// Every tile owns a core of coreWidth x coreHeight DEM texels (the last tile
// of a row or column owns fewer when the DEM ends) and carries a border of
// `border` texels on each side copied from its neighbours, or clamped to the
// DEM's edge, so a bilinear fetch near a core's edge reads only its own tile
// and gives what the single image would give. Tiles are layers of 2D array
// images ("pages", one allocation each); tile i is layer i % layersPerPage of
// page i / layersPerPage, rows of tiles from the north-west.
#pragma once

#include <cstdint>
#include <string>

#include <glm/vec2.hpp>

#include "config.h"

namespace aal {

// Border texels per side: one for the bilinear footprint at the far edge of
// a core, one for rounding of the coordinate near it.
constexpr uint32_t kTerrainTileBorder = AAL_TERRAIN_TILE_BORDER;
// Pages per texture kind that the shaders bind.
constexpr uint32_t kTerrainTilePages = AAL_TERRAIN_TILE_PAGES;
// The DEM's textures, in the shaders' binding order (terrain_textures.glsl).
enum class TerrainTexture : int { Height = 0, Aperture = 1, Albedo = 2 };
constexpr int kTerrainTextureKinds = 3;
// Bytes per texel: R32F heights, RGBA16F apertures, RGBA8 albedo. Tiles are
// sized so that one aperture layer fits an allocation; each kind then packs
// as many layers into a page as fit.
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
  uint32_t border = 0;  // 0 for a single tile: its image is the DEM
  // Per TerrainTexture: tiles (layers) per page, and pages.
  uint32_t layersPerPage[kTerrainTextureKinds] = {1, 1, 1};
  uint32_t pages[kTerrainTextureKinds] = {1, 1, 1};

  uint32_t tileCount() const { return tilesX * tilesY; }
  uint32_t imageWidth() const { return coreWidth + 2 * border; }
  uint32_t imageHeight() const { return coreHeight + 2 * border; }
  uint32_t layersPerPageOf(TerrainTexture kind) const { return layersPerPage[int(kind)]; }
  uint32_t pagesOf(TerrainTexture kind) const { return pages[int(kind)]; }
  // Layers in page `page` of `kind` (the last page may hold fewer).
  uint32_t layersIn(TerrainTexture kind, uint32_t page) const;
  // Texels of all tiles of one kind, borders and unused overhang included.
  uint64_t texelsPerKind() const { return uint64_t{imageWidth()} * imageHeight() * tileCount(); }
};

// One tile when the DEM fits one image of the device (and maxTileTexels)
// and its apertures one allocation; otherwise tiles of at most
// min(maxTileTexels, maxImageDimension - 2 border) texels across, as even as
// possible, one aperture layer fitting an allocation. Throws
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
