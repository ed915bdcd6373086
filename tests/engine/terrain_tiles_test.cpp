// The tile layout and lookup of engine/terrain_tiles.h: how DEMs are split,
// that a bilinear fetch through the lookup from tile images built as the
// scene builds them (borders copied from the neighbours, clamped at the DEM's
// edge) gives the single image's clamped bilinear value everywhere, and that
// the GLSL twin (shaders/tile_lookup.glsl) answers exactly as the C++.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <glm/vec4.hpp>

#include "aperture/engine/terrain_tiles.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/shaders/config.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

TerrainTileLimits lavapipeLimits(uint32_t maxTileTexels = 0) {
  TerrainTileLimits limits;  // lavapipe's: 16384, 2048 layers, 2 GiB per allocation
  limits.maxTileTexels = maxTileTexels;
  return limits;
}

TEST(TerrainTiles, ADemThatFitsOneImageIsOneTileWithItsBorder) {
  const TerrainTileLayout t = planTerrainTiles(300, 200, lavapipeLimits());
  EXPECT_EQ(t.tileCount(), 1u);
  EXPECT_EQ(t.border, 64u);
  // 300 + 2 x 64 and 200 + 2 x 64, rounded up to whole texels of the
  // coarsest mip level (32 DEM texels).
  EXPECT_EQ(t.imageWidth(), 448u);
  EXPECT_EQ(t.imageHeight(), 352u);
  EXPECT_EQ(t.pagesOf(TerrainTexture::Aperture), 1u);
  // The forced size does not split a DEM that fits it.
  EXPECT_EQ(planTerrainTiles(300, 200, lavapipeLimits(300)).tileCount(), 1u);
}

TEST(TerrainTiles, AForcedTileSizeSplitsEvenly) {
  const TerrainTileLayout t = planTerrainTiles(300, 200, lavapipeLimits(64));
  EXPECT_EQ(t.tilesX, 5u);
  EXPECT_EQ(t.tilesY, 4u);
  // Cores are whole texels of the coarsest mip level, so that every tile's
  // levels average the same DEM texels as the whole DEM's would.
  EXPECT_EQ(t.coreWidth, 64u);
  EXPECT_EQ(t.coreHeight, 64u);
  EXPECT_EQ(t.border, 64u);
  EXPECT_EQ(t.imageWidth(), 192u);
  for (const TerrainTexture kind :
       {TerrainTexture::Height, TerrainTexture::Aperture, TerrainTexture::Albedo}) {
    EXPECT_EQ(t.pagesOf(kind), 1u);
    EXPECT_EQ(t.layersPerPageOf(kind), 20u);
  }
  // At most 100 texels: cores of 96, as few tiles as that allows.
  const TerrainTileLayout u = planTerrainTiles(403, 344, lavapipeLimits(100));
  EXPECT_EQ(u.tilesX, 5u);
  EXPECT_EQ(u.tilesY, 4u);
  EXPECT_EQ(u.coreWidth, 96u);
  EXPECT_EQ(u.coreHeight, 96u);
  // Below the alignment: cores of one coarsest texel.
  EXPECT_EQ(planTerrainTiles(300, 200, lavapipeLimits(1)).coreWidth, 32u);
}

TEST(TerrainTiles, DemsBeyondTheDeviceAreTiledToFitItsImagesAndAllocations) {
  // 16384^2 fits the side limit, but its RGBA16F aperture is 2 GiB: tiled.
  const TerrainTileLayout a = planTerrainTiles(16384, 16384, lavapipeLimits());
  EXPECT_GT(a.tileCount(), 1u);
  const TerrainTileLayout b = planTerrainTiles(20000, 20000, lavapipeLimits());
  EXPECT_EQ(b.tilesX, 2u);
  EXPECT_EQ(b.coreWidth, 10016u);
  // Each kind fills its pages: 20000^2's apertures (10144^2 images with
  // their mip levels, 1.1 GB) take a page each, its heights two a page.
  EXPECT_EQ(b.pagesOf(TerrainTexture::Aperture), 4u);
  EXPECT_EQ(b.pagesOf(TerrainTexture::Height), 2u);
  // The largest square DEM in lavapipe's four pages: one 12288^2 aperture
  // tile per page.
  const TerrainTileLayout c = planTerrainTiles(24576, 24576, lavapipeLimits());
  EXPECT_EQ(c.pagesOf(TerrainTexture::Aperture), 4u);
  for (const TerrainTileLayout& t : {a, b, c}) {
    EXPECT_LE(t.imageWidth(), 16384u);
    EXPECT_GE(uint64_t{t.coreWidth} * t.tilesX, t.demWidth);
    EXPECT_GE(uint64_t{t.coreHeight} * t.tilesY, t.demHeight);
    // Every page fits an allocation.
    for (int kind = 0; kind < kTerrainTextureKinds; ++kind) {
      EXPECT_LE(t.layerTexels() * kTerrainTextureBytes[kind] * t.layersPerPage[kind], 1ull << 31);
      EXPECT_GT(t.layerTexels(), uint64_t{t.imageWidth()} * t.imageHeight());  // the mip levels
      // Apertures in up to four pages, the 4-byte kinds in up to two (the
      // paged shaders pick among as many).
      EXPECT_LE(t.pages[kind],
                kind == int(TerrainTexture::Aperture) ? kTerrainTilePages : kTerrainTilePages / 2);
      EXPECT_GE(t.pages[kind] * t.layersPerPage[kind], t.tileCount());
    }
  }
  // A device with 32768-texel images and allocations beyond 11 GiB: one
  // image for 32000^2 (32128^2 with its border); 32768^2 with its border
  // no longer fits one.
  TerrainTileLimits big;
  big.maxImageDimension = 32768;
  big.maxAllocationBytes = uint64_t{64} << 30;
  EXPECT_EQ(planTerrainTiles(32000, 32000, big).tileCount(), 1u);
  EXPECT_EQ(planTerrainTiles(32768, 32768, big).tileCount(), 4u);
}

TEST(TerrainTiles, TooManyPagesIsAClearError) {
  // 32768^2 on lavapipe: 3x3 tiles, one aperture tile per 2 GiB page.
  EXPECT_THROW(planTerrainTiles(32768, 32768, lavapipeLimits()), std::runtime_error);
  try {
    planTerrainTiles(100000, 100000, lavapipeLimits());
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("100000x100000 texels"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("pages"), std::string::npos) << e.what();
  }
}

// A small DEM of distinct values and its tiles, built texel by texel the way
// the scene fills them (core + border, clamped to the DEM's edge).
struct TiledField {
  TerrainTileLayout layout;
  std::vector<float> dem;
  std::vector<std::vector<float>> tiles;  // rows of tiles from the north-west

  TiledField(uint32_t width, uint32_t height, uint32_t maxTile) {
    layout = planTerrainTiles(width, height, lavapipeLimits(maxTile));
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> value(0.0f, 1000.0f);
    dem.resize(size_t{width} * height);
    for (float& v : dem) v = value(rng);
    for (uint32_t ty = 0; ty < layout.tilesY; ++ty) {
      for (uint32_t tx = 0; tx < layout.tilesX; ++tx) {
        std::vector<float>& image = tiles.emplace_back();
        for (uint32_t r = 0; r < layout.imageHeight(); ++r) {
          for (uint32_t c = 0; c < layout.imageWidth(); ++c) {
            image.push_back(demAt(int64_t{tx} * layout.coreWidth - layout.border + c,
                                  int64_t{ty} * layout.coreHeight - layout.border + r));
          }
        }
      }
    }
  }
  float demAt(int64_t col, int64_t row) const {
    col = std::clamp<int64_t>(col, 0, layout.demWidth - 1);
    row = std::clamp<int64_t>(row, 0, layout.demHeight - 1);
    return dem[size_t(row) * layout.demWidth + size_t(col)];
  }
};

// Bilinear with clamp-to-edge, as a sampler does, from a w x h image;
// `inside` reports whether the footprint needed no clamping.
double bilinear(const std::vector<float>& image, uint32_t w, uint32_t h, double x, double y,
                bool* inside) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t x0 = int64_t(fx), y0 = int64_t(fy);
  *inside = x0 >= 0 && y0 >= 0 && x0 + 1 < int64_t{w} && y0 + 1 < int64_t{h};
  const auto at = [&](int64_t c, int64_t r) {
    return double(image[size_t(std::clamp<int64_t>(r, 0, h - 1)) * w +
                        size_t(std::clamp<int64_t>(c, 0, w - 1))]);
  };
  const double ax = x - fx, ay = y - fy;
  return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
         ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
}

TEST(TerrainTiles, BilinearFetchesThroughTheLookupMatchTheSingleImage) {
  const TiledField f(300, 200, 64);
  ASSERT_EQ(f.layout.tileCount(), 20u);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> col(-20.0f, 320.0f), row(-20.0f, 220.0f);
  std::vector<glm::vec2> positions;
  for (int i = 0; i < 200000; ++i) positions.push_back({col(rng), row(rng)});
  // Right at and around every seam and the DEM's edges.
  for (uint32_t s = 0; s <= f.layout.tilesX; ++s) {
    for (float d : {-1.0f, -0.5f, -1e-4f, 0.0f, 1e-4f, 0.5f, 1.0f}) {
      for (float r = -1.0f; r <= 200.0f; r += 0.37f) {
        positions.push_back({float(s * f.layout.coreWidth) + d, r});
        positions.push_back(
            {r * 1.5f, float(std::min(s, f.layout.tilesY) * f.layout.coreHeight) + d});
      }
    }
  }
  double worst = 0;
  for (const glm::vec2 p : positions) {
    const TerrainTileTexel t = terrainTileTexel(f.layout, TerrainTexture::Height, p);
    const uint32_t perPage = f.layout.layersPerPageOf(TerrainTexture::Height);
    ASSERT_GE(t.page, 0);
    ASSERT_LT(t.layer, int(perPage));
    const size_t tile = size_t(t.page) * perPage + size_t(t.layer);
    ASSERT_LT(tile, f.tiles.size());
    bool inTile = false, inDem = false;
    const double tiled = bilinear(f.tiles[tile], f.layout.imageWidth(), f.layout.imageHeight(),
                                  double(t.uv.x) * f.layout.imageWidth() - 0.5,
                                  double(t.uv.y) * f.layout.imageHeight() - 0.5, &inTile);
    const double single = bilinear(f.dem, 300, 200, p.x, p.y, &inDem);
    // Within the DEM and one texel beyond it the border holds the whole
    // footprint; farther out the image's clamp repeats the edge as the
    // single image's does.
    if (p.x >= -1 && p.x <= 300 && p.y >= -1 && p.y <= 200) {
      ASSERT_TRUE(inTile) << p.x << " " << p.y;
    }
    // The coordinate went through float: it may differ by a rounding of
    // the position (values up to 1000, positions up to 320).
    worst = std::max(worst, std::abs(tiled - single));
    ASSERT_NEAR(tiled, single, 0.05) << p.x << " " << p.y;
  }
  std::printf("%zu positions, worst difference %.3g (values 0..1000)\n", positions.size(), worst);
}

class TileLookupParity : public VulkanTest {};

TEST_F(TileLookupParity, GlslLookupMatchesCpp) {
  for (const uint32_t maxTile : {0u, 64u, 37u}) {
    TerrainTileLimits limits = lavapipeLimits(maxTile);
    if (maxTile == 37) {
      // 70 tiles of 32^2: 18 aperture layers a page, four pages (heights:
      // two).
      const uint64_t apertureLayer = planTerrainTiles(300, 200, limits).layerTexels() * 8;
      limits.maxAllocationBytes = (18 * apertureLayer + 1) * 16 / 15 + 16;
    }
    const TerrainTileLayout layout = planTerrainTiles(300, 200, limits);
    const glm::ivec4 tiles[2] = {
        glm::ivec4(glm::uvec4(layout.coreWidth, layout.coreHeight, layout.tilesX, layout.tilesY)),
        glm::ivec4(glm::uvec4(layout.border, layout.layersPerPageOf(TerrainTexture::Aperture),
                              layout.imageWidth(), layout.imageHeight()))};
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> col(-30.0f, 330.0f), row(-30.0f, 230.0f);
    std::vector<glm::vec2> texels;
    for (int i = 0; i < 50000; ++i) texels.push_back({col(rng), row(rng)});
    for (uint32_t s = 0; s <= layout.tilesX; ++s) {
      const float seam = float(s * layout.coreWidth);
      for (float d : {-1e-4f, 0.0f, 1e-4f}) texels.push_back({seam + d, seam * 0.5f + d});
    }
    const uint32_t count = static_cast<uint32_t>(texels.size());
    Buffer layoutBuffer(device(), sizeof tiles, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                        MemoryIntent::Upload);
    layoutBuffer.write(tiles, sizeof tiles);
    Buffer input(device(), count * sizeof(glm::vec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryIntent::Upload);
    input.write(texels.data(), count * sizeof(glm::vec2));
    Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                  MemoryIntent::Readback);
    const ComputePipeline pipeline(device(), "tile_lookup_parity.comp", sizeof(uint32_t));
    const uint32_t groups = (count + AAL_TILE_PARITY_GROUP_SIZE - 1) / AAL_TILE_PARITY_GROUP_SIZE;
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      pipeline.record(cmd, {&layoutBuffer, &input, &output}, &count, groups);
    });
    std::vector<glm::vec4> answers(count);
    output.read(answers.data(), count * sizeof(glm::vec4));
    // The device's division need not be correctly rounded: the normalised
    // coordinate may differ by an ulp or two, and right at a seam (within a
    // rounding of texel / core) the tile may be the neighbour, whose border
    // holds the same texels. So: the same tile away from seams, and both
    // answers address the queried DEM position.
    const auto position = [&](int page, int layer, glm::vec2 uv, int axis) {
      const int tile = page * int(layout.layersPerPageOf(TerrainTexture::Aperture)) + layer;
      const int tileCol = tile % int(layout.tilesX), tileRow = tile / int(layout.tilesX);
      return axis == 0 ? double(uv.x) * layout.imageWidth() - 0.5 - layout.border +
                             double(tileCol) * layout.coreWidth
                       : double(uv.y) * layout.imageHeight() - 0.5 - layout.border +
                             double(tileRow) * layout.coreHeight;
    };
    int pagesSeen = 0, otherTile = 0;
    double worstUlps = 0;
    for (uint32_t i = 0; i < count; ++i) {
      const TerrainTileTexel t = terrainTileTexel(layout, TerrainTexture::Aperture, texels[i]);
      const glm::vec4 gpu = answers[i];
      const bool sameTile = gpu.z == float(t.page) && gpu.w == float(t.layer);
      if (!sameTile) {
        ++otherTile;
        const double toSeamX = std::abs(std::remainder(double(texels[i].x), layout.coreWidth));
        const double toSeamY = std::abs(std::remainder(double(texels[i].y), layout.coreHeight));
        ASSERT_LT(std::min(toSeamX, toSeamY), 1e-3) << i << " away from a seam";
      } else {
        for (int c = 0; c < 2; ++c) {
          const float cpu = t.uv[c];
          const double ulp = std::nextafter(std::abs(cpu), INFINITY) - std::abs(cpu);
          worstUlps = std::max(worstUlps, std::abs(double(gpu[c]) - cpu) / ulp);
        }
      }
      for (int c = 0; c < 2; ++c) {
        ASSERT_NEAR(position(int(gpu.z), int(gpu.w), glm::vec2(gpu), c), texels[i][c], 1e-3) << i;
        ASSERT_NEAR(position(t.page, t.layer, t.uv, c), texels[i][c], 1e-3) << i;
      }
      pagesSeen = std::max(pagesSeen, t.page + 1);
    }
    std::printf("%s: %u queries, %d in the neighbouring tile at a seam, worst uv %.1f ulp\n",
                describeTerrainTiles(layout).c_str(), count, otherTile, worstUlps);
    EXPECT_LE(worstUlps, 2.0);
    EXPECT_EQ(uint32_t(pagesSeen), layout.pagesOf(TerrainTexture::Aperture));
  }
}

}  // namespace
}  // namespace aal
