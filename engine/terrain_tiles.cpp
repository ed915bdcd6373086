#include "aperture/engine/terrain_tiles.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace aal {

namespace {

uint32_t ceilDiv(uint32_t a, uint32_t b) {
  return (a + b - 1) / b;
}

// Texels of a width x height image with kTerrainMipLevels levels (sizes
// multiples of the alignment).
uint64_t mipChainTexels(uint32_t width, uint32_t height) {
  uint64_t texels = 0;
  for (uint32_t level = 0; level < kTerrainMipLevels; ++level) {
    texels += uint64_t{std::max(1u, width >> level)} * std::max(1u, height >> level);
  }
  return texels;
}

}  // namespace

uint64_t TerrainTileLayout::layerTexels() const {
  return mipChainTexels(imageWidth(), imageHeight());
}

uint32_t TerrainTileLayout::layersIn(TerrainTexture kind, uint32_t page) const {
  const uint32_t perPage = layersPerPageOf(kind), first = page * perPage;
  return first >= tileCount() ? 0 : std::min(perPage, tileCount() - first);
}

TerrainTileLayout planTerrainTiles(uint32_t demWidth, uint32_t demHeight,
                                   const TerrainTileLimits& limits) {
  if (demWidth == 0 || demHeight == 0) throw std::invalid_argument("empty DEM");
  TerrainTileLayout t;
  t.demWidth = demWidth;
  t.demHeight = demHeight;
  // Allocations are asked for with some slack: an image may need a little
  // more memory than its texels.
  const uint64_t allocation = limits.maxAllocationBytes / 16 * 15;
  const uint32_t forced = limits.maxTileTexels > 0 ? limits.maxTileTexels : UINT32_MAX;
  const uint64_t widest = kTerrainTextureBytes[int(TerrainTexture::Aperture)];
  t.coreWidth = demWidth;
  t.coreHeight = demHeight;
  if (demWidth <= forced && demHeight <= forced && t.imageWidth() <= limits.maxImageDimension &&
      t.imageHeight() <= limits.maxImageDimension && t.layerTexels() * widest <= allocation) {
    return t;
  }

  const int64_t align = kTerrainMipAlignment;
  const int64_t bySide = int64_t{limits.maxImageDimension} - 2 * t.border;
  // The mip levels add at most a third to level 0.
  const int64_t byAllocation =
      int64_t(std::sqrt(double(allocation / widest) * 0.75)) - 2 * t.border;
  const int64_t maxCore =
      std::max(align, std::min({int64_t{forced}, bySide, byAllocation}) / align * align);
  const auto split = [&](uint32_t texels, uint32_t& tiles, uint32_t& core) {
    tiles = ceilDiv(texels, static_cast<uint32_t>(maxCore));
    core = TerrainTileLayout::alignedToMips(ceilDiv(texels, tiles));
    tiles = ceilDiv(texels, core);
  };
  split(demWidth, t.tilesX, t.coreWidth);
  split(demHeight, t.tilesY, t.coreHeight);
  for (int kind = 0; kind < kTerrainTextureKinds; ++kind) {
    const uint64_t layerBytes = t.layerTexels() * kTerrainTextureBytes[kind];
    const uint64_t layers =
        std::clamp<uint64_t>(allocation / layerBytes, 1, std::max(1u, limits.maxArrayLayers));
    t.layersPerPage[kind] = static_cast<uint32_t>(std::min<uint64_t>(layers, t.tileCount()));
    t.pages[kind] = ceilDiv(t.tileCount(), t.layersPerPage[kind]);
  }
  // The shaders pick among all pages for the apertures but among half of
  // them for the 4-byte kinds (terrain_textures.glsl), which fit twice as
  // many layers a page: so they need no more wherever the apertures fit.
  const uint32_t halfPages = kTerrainTilePages / 2;
  if (t.pages[int(TerrainTexture::Aperture)] > kTerrainTilePages ||
      t.pages[int(TerrainTexture::Height)] > halfPages ||
      t.pages[int(TerrainTexture::Albedo)] > halfPages) {
    throw std::runtime_error(describeTerrainTiles(t) + ": more texture pages than the " +
                             std::to_string(kTerrainTilePages) + " of apertures and " +
                             std::to_string(halfPages) +
                             " of heights and albedo the renderer binds (a smaller DEM, or a "
                             "device with larger images or allocations, is needed)");
  }
  return t;
}

TerrainTileTexel terrainTileTexel(const TerrainTileLayout& t, TerrainTexture kind,
                                  glm::vec2 texel) {
  // The same single-precision steps as terrainTileTexel in tile_lookup.glsl.
  const glm::vec2 core(float(t.coreWidth), float(t.coreHeight));
  const int tileX = std::clamp(int(std::floor(texel.x / core.x)), 0, int(t.tilesX) - 1);
  const int tileY = std::clamp(int(std::floor(texel.y / core.y)), 0, int(t.tilesY) - 1);
  const glm::vec2 local =
      texel - glm::vec2(float(tileX * int(t.coreWidth)), float(tileY * int(t.coreHeight))) +
      float(t.border);
  const int index = tileY * int(t.tilesX) + tileX;
  TerrainTileTexel r;
  const int perPage = int(t.layersPerPageOf(kind));
  r.page = index / perPage;
  r.layer = index % perPage;
  r.uv = (local + 0.5f) / glm::vec2(float(t.imageWidth()), float(t.imageHeight()));
  return r;
}

std::string describeTerrainTiles(const TerrainTileLayout& t) {
  return std::to_string(t.demWidth) + "x" + std::to_string(t.demHeight) + " texels in " +
         std::to_string(t.tilesX) + "x" + std::to_string(t.tilesY) + " tiles of " +
         std::to_string(t.coreWidth) + "x" + std::to_string(t.coreHeight) + " (+" +
         std::to_string(t.border) + " border), pages of heights/apertures/albedo " +
         std::to_string(t.pages[0]) + "/" + std::to_string(t.pages[1]) + "/" +
         std::to_string(t.pages[2]);
}

}  // namespace aal
