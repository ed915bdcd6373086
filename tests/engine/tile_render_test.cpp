// Tiled terrain textures (engine/terrain_tiles.h) in the renderer: a small
// fBm DEM rendered from one image and from forced 64-texel tiles (20 tiles in
// one page per kind; the apertures in two pages; every kind in several: the
// three shader variants of terrain_textures.glsl) gives the same picture in
// every shading mode
// that samples the terrain's textures, with the obscurance passes on (their
// samples reach across tiles), from above (pixels ~ texels, so the seams are
// known columns and rows) and from an oblique view (LOD patches with morphing
// vertices straddle the seams).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>

#include <Imath/half.h>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/deletion_queue.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/albedo_image.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr int kWidth = 300, kHeight = 200;  // DEM texels; the top view's pixels
constexpr double kCellM = 30.0;
constexpr uint32_t kTile = 64;  // forced: 5 x 4 tiles of 64 x 64 texels

Heightfield fbm() {
  SyntheticTerrainOptions o;
  o.width = kWidth;
  o.height = kHeight;
  o.cellSizeM = kCellM;
  o.featureSizeTexels = 48;
  o.seed = 4;
  return makeSyntheticTerrain(o);
}

// Smoothly varying colours, so albedo fetches across a seam show.
AlbedoImage albedo() {
  AlbedoImage a;
  a.width = kWidth;
  a.height = kHeight;
  for (int row = 0; row < kHeight; ++row) {
    for (int col = 0; col < kWidth; ++col) {
      a.rgb.push_back(0.35f + 0.3f * std::sin(col / 7.0f));
      a.rgb.push_back(0.35f + 0.3f * std::cos(row / 5.0f));
      a.rgb.push_back(0.3f + 0.2f * std::sin((col + row) / 11.0f));
    }
  }
  return a;
}

FrameSettings lighting(ShadingMode mode) {
  FrameSettings s;
  s.mode = mode;
  setSunAndSky(s.lighting, 230, 25, 2.5);
  s.lighting.exposure = 0.07f;
  s.obscurance.radiusM = 400;  // about 13 texels: samples cross the seams
  return s;
}

// Straight down from high above: pixel (i, j) sees about texel (i, j).
FrameSettings topView(ShadingMode mode) {
  FrameSettings s = lighting(mode);
  s.camera.position = {0, 0, 60000};
  s.camera.lookAt = {0, 0, 0};
  s.camera.verticalFovDeg = 2 * std::atan(0.5 * kHeight * kCellM / 60000) * 180 / std::numbers::pi;
  return s;
}

FrameSettings obliqueView(ShadingMode mode) {
  FrameSettings s = lighting(mode);
  s.camera.position = {-5200, -3900, 2600};
  s.camera.lookAt = {600, 300, 0};
  s.camera.verticalFovDeg = 45;
  return s;
}

struct Difference {
  int maxLsb = 0;         // largest 8-bit difference of any channel
  size_t pixelsOff = 0;   // pixels with any channel different
  int maxLsbAtSeams = 0;  // within 2 pixels of a seam column or row (top view)
  // Pixels beyond 1 LSB, and the largest of their differences not explained
  // by an edge of the reference picture: a pixel whose view ray grazes a
  // silhouette may see another surface when a vertex height rounds
  // differently, and then differs by up to the jump to a neighbour there.
  size_t pixelsBeyondOne = 0;
  int maxBeyondEdge = 0;
};

int channelAt(const FrameResult& f, int x, int y, int c) {
  x = std::clamp(x, 0, int(f.width) - 1);
  y = std::clamp(y, 0, int(f.height) - 1);
  return f.display[4 * (size_t(y) * f.width + size_t(x)) + size_t(c)];
}

Difference compare(const FrameResult& a, const FrameResult& reference, bool topViewSeams) {
  Difference d;
  for (int y = 0; y < int(a.height); ++y) {
    for (int x = 0; x < int(a.width); ++x) {
      int worst = 0, edge = 0;
      for (int c = 0; c < 3; ++c) {
        const int r = channelAt(reference, x, y, c);
        worst = std::max(worst, std::abs(channelAt(a, x, y, c) - r));
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            edge = std::max(edge, std::abs(channelAt(reference, x + dx, y + dy, c) - r));
          }
        }
      }
      d.maxLsb = std::max(d.maxLsb, worst);
      if (worst > 0) ++d.pixelsOff;
      if (worst > 1) {
        ++d.pixelsBeyondOne;
        d.maxBeyondEdge = std::max(d.maxBeyondEdge, worst - edge);
      }
      const int sx = x % int(kTile), sy = y % int(kTile);
      const bool seam = std::min(sx, int(kTile) - sx) <= 2 || std::min(sy, int(kTile) - sy) <= 2;
      if (topViewSeams && seam) d.maxLsbAtSeams = std::max(d.maxLsbAtSeams, worst);
    }
  }
  return d;
}

// A tiled scene's picture against the single image's, printed and checked.
// Tolerance: 1 LSB of the 8-bit output (a fetch's coordinate rounds
// differently in a tile's image: heights differ by ~1e-5 of a texel's
// slope), none more at the seams, and a handful of pixels (<= 0.01%)
// beyond it, each on an edge of the picture that explains its difference.
void expectTiledAsOneImage(const Difference& d, const std::string& what) {
  std::printf("%s: max %d LSB (seams %d), %zu of %d pixels differ, %zu beyond 1 LSB\n",
              what.c_str(), d.maxLsb, d.maxLsbAtSeams, d.pixelsOff, kWidth * kHeight,
              d.pixelsBeyondOne);
  EXPECT_LE(d.maxLsbAtSeams, 1) << what;
  EXPECT_LE(d.pixelsOff, size_t(kWidth * kHeight / 1000)) << what;
  EXPECT_LE(d.pixelsBeyondOne, size_t(kWidth * kHeight / 10000)) << what;
  EXPECT_LE(d.maxBeyondEdge, 1) << what;
}

class TileRender : public VulkanTest {};

// The texels of mip level `level` of layer `layer` of a texture page, as
// bytes.
std::vector<unsigned char> readLevelBytes(const Device& device, const Image& page, uint32_t layer,
                                          uint32_t level, size_t bytesPerTexel) {
  const uint32_t w = page.desc().width >> level, h = page.desc().height >> level;
  const size_t bytes = size_t{w} * h * bytesPerTexel;
  Buffer out(device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  submitAndWait(device, [&](VkCommandBuffer cmd) {
    transitionImage(cmd, page, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    VkBufferImageCopy region{};
    region.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, level, layer, 1};
    region.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(cmd, page.handle(), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, out.handle(),
                           1, &region);
    transitionImage(cmd, page, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                    VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
  });
  std::vector<unsigned char> texels(bytes);
  out.read(texels.data(), bytes);
  return texels;
}

// R32F texels of mip level `level` of layer `layer` of a texture page.
std::vector<float> readLevel(const Device& device, const Image& page, uint32_t layer,
                             uint32_t level) {
  const std::vector<unsigned char> bytes = readLevelBytes(device, page, layer, level, 4);
  std::vector<float> texels(bytes.size() / 4);
  std::memcpy(texels.data(), bytes.data(), bytes.size());
  return texels;
}

// Every level of every kind is the mean of the 2 x 2 texels of the level
// above (read back from the device, the means recomputed here in double):
// heights to float rounding, apertures to half-float rounding, albedo to
// 8-bit rounding.
TEST_F(TileRender, EveryMipLevelIsTheMeanOfTheLevelAbove) {
  const Heightfield field = fbm();
  BakeOptions bake;
  bake.azimuths = 8;
  const ApertureMap aperture = bakeApertures(field, bake).aperture;
  const AlbedoImage colours = albedo();
  const TerrainScene scene(device(), field, aperture, &colours, 400000);
  struct Kind {
    const Image& page;
    int channels;
    size_t channelBytes;
    double tolerance;  // relative to max(1, |mean|)
  };
  const Kind kinds[] = {{scene.heightPages()[0], 1, 4, 1e-6},
                        {scene.aperturePages()[0], 4, 2, 1e-3},
                        {scene.albedoPages()[0], 4, 1, 0.51}};
  for (const Kind& kind : kinds) {
    const auto value = [&](const std::vector<unsigned char>& texels, size_t i) -> double {
      if (kind.channelBytes == 4) {
        float f;
        std::memcpy(&f, &texels[4 * i], 4);
        return f;
      }
      if (kind.channelBytes == 1) return texels[i];
      Imath::half h;
      h.setBits(static_cast<uint16_t>(texels[2 * i] | texels[2 * i + 1] << 8));
      return float(h);
    };
    const size_t texelBytes = kind.channels * kind.channelBytes;
    std::vector<unsigned char> upper = readLevelBytes(device(), kind.page, 0, 0, texelBytes);
    for (uint32_t level = 1; level < kTerrainMipLevels; ++level) {
      const std::vector<unsigned char> texels =
          readLevelBytes(device(), kind.page, 0, level, texelBytes);
      const uint32_t w = kind.page.desc().width >> level, h = kind.page.desc().height >> level;
      double worst = 0;
      for (uint32_t r = 0; r < h; ++r) {
        for (uint32_t c = 0; c < w; ++c) {
          for (int k = 0; k < kind.channels; ++k) {
            const auto above = [&](uint32_t dr, uint32_t dc) {
              return value(upper, (size_t{2 * r + dr} * 2 * w + 2 * c + dc) * kind.channels + k);
            };
            const double mean = (above(0, 0) + above(0, 1) + above(1, 0) + above(1, 1)) / 4;
            const double got = value(texels, (size_t{r} * w + c) * kind.channels + k);
            worst = std::max(worst, std::abs(got - mean) / std::max(1.0, std::abs(mean)));
          }
        }
      }
      EXPECT_LE(worst, kind.tolerance) << "bytes per texel " << texelBytes << " level " << level;
      upper = texels;
    }
  }
}

// Every tile's mip levels hold the whole DEM's levels over the tile's
// window (cores, borders and image sizes are whole texels of the coarsest
// level), so a fetch at any level of detail reads the same values tiled or
// not: the heights, bit for bit.
TEST_F(TileRender, EveryTilesMipLevelsAreTheWholeDemsLevels) {
  const Heightfield field = fbm();
  const TerrainScene single(device(), field, nullptr, 400000);
  const TerrainScene tiled(device(), field, nullptr, 400000, {kTile, 0});
  const TerrainTileLayout& whole = single.tiles();
  const TerrainTileLayout& t = tiled.tiles();
  ASSERT_EQ(whole.border, t.border);
  ASSERT_EQ(t.pagesOf(TerrainTexture::Height), 1u);
  for (uint32_t level = 0; level < kTerrainMipLevels; ++level) {
    const std::vector<float> reference = readLevel(device(), single.heightPages()[0], 0, level);
    const uint32_t referenceWidth = whole.imageWidth() >> level;
    const uint32_t referenceHeight = whole.imageHeight() >> level;
    size_t compared = 0, different = 0;
    for (uint32_t tile = 0; tile < t.tileCount(); ++tile) {
      const std::vector<float> texels = readLevel(device(), tiled.heightPages()[0], tile, level);
      const uint32_t w = t.imageWidth() >> level, h = t.imageHeight() >> level;
      // Both images start `border` texels before their first core texel.
      const uint32_t offsetX = (tile % t.tilesX) * t.coreWidth >> level;
      const uint32_t offsetY = (tile / t.tilesX) * t.coreHeight >> level;
      for (uint32_t r = 0; r < h && offsetY + r < referenceHeight; ++r) {
        for (uint32_t c = 0; c < w && offsetX + c < referenceWidth; ++c) {
          ++compared;
          if (texels[size_t{r} * w + c] !=
              reference[size_t{offsetY + r} * referenceWidth + offsetX + c]) {
            ++different;
          }
        }
      }
    }
    EXPECT_GT(compared, 0u);
    EXPECT_EQ(different, 0u) << "level " << level << ": " << different << " of " << compared;
  }
}

// Slopes (xy: dz/dx east, dz/dy north) of mip level `level` of a slope
// page: RG16F (zw 0), or RGBA16F with the horizon pair in zw.
std::vector<glm::vec4> readSlopes(const Device& device, const Image& page, uint32_t layer,
                                  uint32_t level) {
  const size_t channels = page.desc().format == VK_FORMAT_R16G16B16A16_SFLOAT ? 4 : 2;
  const std::vector<unsigned char> bytes = readLevelBytes(device, page, layer, level, 2 * channels);
  std::vector<glm::vec4> slopes(bytes.size() / (2 * channels), glm::vec4(0.0f));
  for (size_t i = 0; i < slopes.size(); ++i) {
    for (size_t k = 0; k < channels; ++k) {
      const unsigned char* b = &bytes[2 * (channels * i + k)];
      Imath::half v;
      v.setBits(static_cast<uint16_t>(b[0] | b[1] << 8));
      slopes[i][int(k)] = float(v);
    }
  }
  return slopes;
}

// The slope texture (shaders/slopes.glsl) holds at level 0 of every tile
// the central differences of the heights one texel apart (recomputed here in
// double from the heights read back; the image's edge takes its own texel for
// the missing neighbour), and at each level above the mean of the 2 x 2
// texels below (as read back), to half-float rounding: the mean slope of the
// DEM texels a texel covers. Each tile's slopes equal the single image's over
// the tile's window, each level's outermost texels (which hold the image's
// edge, and which no fetch reaches) aside.
TEST_F(TileRender, SlopesAreTheMeanSlopeOfTheTexelsEachLevelCovers) {
  const Heightfield field = fbm();
  const TerrainScene single(device(), field, nullptr, 400000);
  const TerrainScene tiled(device(), field, nullptr, 400000, {kTile, 0});
  const TerrainTileLayout& whole = single.tiles();
  const TerrainTileLayout& t = tiled.tiles();
  ASSERT_EQ(tiled.slopePages().size(), tiled.heightPages().size());
  std::vector<std::vector<glm::vec4>> below(t.tileCount());  // each tile's level below
  for (uint32_t level = 0; level < kTerrainMipLevels; ++level) {
    const std::vector<glm::vec4> reference = readSlopes(device(), single.slopePages()[0], 0, level);
    const uint32_t referenceWidth = whole.imageWidth() >> level;
    const uint32_t referenceHeight = whole.imageHeight() >> level;
    double worst = 0;
    size_t compared = 0, different = 0;
    for (uint32_t tile = 0; tile < t.tileCount(); ++tile) {
      const std::vector<glm::vec4> slopes =
          readSlopes(device(), tiled.slopePages()[0], tile, level);
      const uint32_t w = t.imageWidth() >> level, h = t.imageHeight() >> level;
      const std::vector<float> heights =
          level == 0 ? readLevel(device(), tiled.heightPages()[0], tile, 0) : std::vector<float>{};
      const auto height = [&](int64_t c, int64_t r) {
        return double(heights[size_t(std::clamp<int64_t>(r, 0, h - 1)) * w +
                              size_t(std::clamp<int64_t>(c, 0, w - 1))]);
      };
      const auto finer = [&](uint32_t c, uint32_t r) {
        return glm::dvec2(below[tile][size_t{r} * (2 * w) + c]);
      };
      const uint32_t offsetX = (tile % t.tilesX) * t.coreWidth >> level;
      const uint32_t offsetY = (tile / t.tilesX) * t.coreHeight >> level;
      for (uint32_t r = 0; r < h; ++r) {
        for (uint32_t c = 0; c < w; ++c) {
          const glm::vec4 got = slopes[size_t{r} * w + c];
          const int64_t x = c, y = r;
          const glm::dvec2 expected =
              level == 0 ? glm::dvec2((height(x + 1, y) - height(x - 1, y)) / (2.0 * kCellM),
                                      (height(x, y - 1) - height(x, y + 1)) / (2.0 * kCellM))
                         : 0.25 * (finer(2 * c, 2 * r) + finer(2 * c + 1, 2 * r) +
                                   finer(2 * c, 2 * r + 1) + finer(2 * c + 1, 2 * r + 1));
          worst =
              std::max({worst, std::abs(got.x - expected.x) / std::max(1.0, std::abs(expected.x)),
                        std::abs(got.y - expected.y) / std::max(1.0, std::abs(expected.y))});
          if (r == 0 || c == 0 || r + 1 == h || c + 1 == w || offsetY + r >= referenceHeight ||
              offsetX + c >= referenceWidth) {
            continue;
          }
          ++compared;
          if (got != reference[size_t{offsetY + r} * referenceWidth + offsetX + c]) ++different;
        }
      }
      below[tile] = slopes;
    }
    EXPECT_LE(worst, 1e-3) << "level " << level;
    EXPECT_GT(compared, 0u);
    EXPECT_EQ(different, 0u) << "level " << level << ": " << different << " of " << compared;
  }
}

TEST_F(TileRender, TiledTexturesRenderAsOneImageInEveryMode) {
  const Heightfield field = fbm();
  BakeOptions bake;
  bake.azimuths = 16;
  const ApertureMap aperture = bakeApertures(field, bake).aperture;
  const AlbedoImage colours = albedo();
  const TerrainScene single(device(), field, aperture, &colours, 400000);
  const TerrainScene onePage(device(), field, aperture, &colours, 400000, {kTile, 0});
  // Pages are filled to 15/16 of their bytes; a layer of heights or albedo
  // is 4 bytes a texel of its image and mip levels, apertures 8.
  const uint64_t layerBytes = onePage.tiles().layerTexels() * 4;
  // Heights and albedo: 20 layers in one page; apertures: 10 in each of two.
  const TerrainScene aperturePages(device(), field, aperture, &colours, 400000,
                                   {kTile, 20 * layerBytes * 16 / 15});
  // Heights and albedo: 10 layers in each of two pages; apertures: 5 in four.
  const TerrainScene allPages(device(), field, aperture, &colours, 400000,
                              {kTile, 10 * layerBytes * 16 / 15});
  ASSERT_EQ(single.tiles().tileCount(), 1u);
  ASSERT_EQ(onePage.tiles().tileCount(), 20u);
  ASSERT_EQ(onePage.tiles().coreWidth, 64u);
  ASSERT_EQ(onePage.tiles().coreHeight, 64u);
  const auto pages = [](const TerrainScene& scene) {
    const TerrainTileLayout& t = scene.tiles();
    return glm::uvec3(t.pagesOf(TerrainTexture::Height), t.pagesOf(TerrainTexture::Aperture),
                      t.pagesOf(TerrainTexture::Albedo));
  };
  ASSERT_EQ(pages(onePage), glm::uvec3(1, 1, 1));
  ASSERT_EQ(pages(aperturePages), glm::uvec3(1, 2, 1));
  ASSERT_EQ(pages(allPages), glm::uvec3(2, 4, 2));
  TerrainRenderer renderer(device(), kWidth, kHeight);

  const ShadingMode modes[] = {ShadingMode::Approx,           ShadingMode::Exact,
                               ShadingMode::BaselineLambert,  ShadingMode::BaselineAo,
                               ShadingMode::DebugVisible,     ShadingMode::DebugBentNormal,
                               ShadingMode::DebugSunFraction, ShadingMode::DebugSkyFill,
                               ShadingMode::DebugObscurance,  ShadingMode::DebugTransfer};
  for (const ShadingMode mode : modes) {
    for (const bool top : {true, false}) {
      const FrameSettings s = top ? topView(mode) : obliqueView(mode);
      const FrameResult reference = renderer.render(single, s, false);
      for (const TerrainScene* tiled : {&onePage, &aperturePages, &allPages}) {
        const FrameResult frame = renderer.render(*tiled, s, false);
        const Difference d = compare(frame, reference, top);
        const std::string what = "mode " + std::to_string(int(mode)) + (top ? " top" : " oblique") +
                                 ", " + describeTerrainTiles(tiled->tiles());
        expectTiledAsOneImage(d, what);
      }
    }
  }
}

// With directional horizons the slope texture's B and A hold the means of
// the horizons (rad) of the pair of directions on the device, and the
// horizon moment texture's R and G the means of their squares
// (engine/terrain_scene.h setHorizons, terrain/light/horizon_moments.h): at
// level 0 of every tile the decoded codes of the DEM texel it covers
// (clamped at the DEM's edge, as every kind's border), to half-float
// rounding (shaders/slopes.glsl decodes as decodeHorizon does), and their
// squares a hair below the stored mean's (so a texel's variance is 0, not
// rounding); at each level above the means of the 2 x 2 texels below, to
// half-float rounding; in every tile the single image's values over the
// tile's window, bit for bit; the slopes in R and G as without horizons. A
// re-lay writes another pair (here the one across direction 0) and leaves
// the slopes as they were. Random codes, 16 directions of 4 bits and 8 of 8.
TEST_F(TileRender, SlopesHoldTheHorizonPairInEveryTile) {
  const Heightfield field = fbm();
  std::mt19937 rng(18);
  for (const auto& [directions, bits] : {std::pair{16, 4}, std::pair{8, 8}}) {
    HorizonMap map;
    map.width = kWidth;
    map.height = kHeight;
    map.directions = directions;
    map.bits = bits;
    std::uniform_int_distribution<int> code(0, (1 << bits) - 1);
    map.codes.resize(size_t(kWidth) * kHeight * size_t(directions));
    for (uint8_t& c : map.codes) c = uint8_t(code(rng));
    TerrainScene single(device(), field, nullptr, 400000);
    TerrainScene tiled(device(), field, nullptr, 400000, {kTile, 0});
    const std::vector<glm::vec4> slopesBefore = readSlopes(device(), tiled.slopePages()[0], 7, 0);
    single.setHorizons(device(), map, 5);
    tiled.setHorizons(device(), map, 5);
    EXPECT_EQ(tiled.slopePages()[0].desc().format, VK_FORMAT_R16G16B16A16_SFLOAT);
    // 4 B of means in the slopes, 4 B of second moments, in each of 20 tiles.
    EXPECT_EQ(tiled.horizonBytes(), tiled.tiles().layerTexels() * 20 * 8);
    ASSERT_EQ(tiled.horizonMomentPages().size(), tiled.slopePages().size());
    EXPECT_EQ(tiled.horizonMomentPages()[0].desc().format, VK_FORMAT_R16G16_SFLOAT);
    for (const int first : {5, directions - 1}) {
      const std::string what = std::to_string(directions) + " directions of " +
                               std::to_string(bits) + " bits, pair " + std::to_string(first);
      if (first != 5) {
        single.relayHorizons(device(), first);
        tiled.relayHorizons(device(), first);
        EXPECT_EQ(tiled.horizonRelays(), 1u) << what;
      }
      ASSERT_EQ(tiled.horizonFirst(), first) << what;
      const int second = (first + 1) % directions;
      const TerrainTileLayout& t = tiled.tiles();
      const uint32_t referenceWidth = single.tiles().imageWidth();
      const uint32_t referenceHeight = single.tiles().imageHeight();
      double worst = 0, worstMean = 0, worstSecond = 0;
      size_t compared = 0, different = 0;
      for (uint32_t level = 0; level < kTerrainMipLevels; ++level) {
        const std::vector<glm::vec4> reference =
            readSlopes(device(), single.slopePages()[0], 0, level);
        const std::vector<glm::vec4> referenceMoments =
            readSlopes(device(), single.horizonMomentPages()[0], 0, level);
        for (uint32_t tile = 0; tile < t.tileCount(); ++tile) {
          const std::vector<glm::vec4> slopes =
              readSlopes(device(), tiled.slopePages()[0], tile, level);
          const std::vector<glm::vec4> moments =
              readSlopes(device(), tiled.horizonMomentPages()[0], tile, level);
          const uint32_t w = t.imageWidth() >> level, h = t.imageHeight() >> level;
          const uint32_t offsetX = (tile % t.tilesX) * t.coreWidth >> level;
          const uint32_t offsetY = (tile / t.tilesX) * t.coreHeight >> level;
          std::vector<glm::vec4> below, momentsBelow;
          if (level > 0) {
            below = readSlopes(device(), tiled.slopePages()[0], tile, level - 1);
            momentsBelow = readSlopes(device(), tiled.horizonMomentPages()[0], tile, level - 1);
          }
          for (uint32_t r = 0; r < h; ++r) {
            for (uint32_t c = 0; c < w; ++c) {
              const glm::vec4 got = slopes[size_t{r} * w + c];
              const glm::vec4 gotSecond = moments[size_t{r} * w + c];
              if (level == 0) {
                for (const auto& [mean, secondMoment] :
                     {std::pair{got.z, gotSecond.x}, std::pair{got.w, gotSecond.y}}) {
                  const double square = double(mean) * mean;
                  ASSERT_LE(secondMoment, square) << what << ", tile " << tile;
                  // The hair (2^-11) and one half-float step down (lavapipe's
                  // stores truncate), or the subnormals' step (2^-24) near 0.
                  ASSERT_GE(secondMoment, square * (1.0 - 3.0 / 2048.0) - 0x1p-24)
                      << what << ", tile " << tile;
                }
                const int col = std::clamp(int(offsetX + c) - int(t.border), 0, kWidth - 1);
                const int row = std::clamp(int(offsetY + r) - int(t.border), 0, kHeight - 1);
                const uint8_t* codes = map.texel(col, row);
                for (const auto& [got1, k] : {std::pair{got.z, first}, std::pair{got.w, second}}) {
                  const double expected = decodeHorizon(codes[k], bits);
                  worst = std::max(worst, std::abs(got1 - expected));
                  ASSERT_NEAR(got1, expected, 1e-3 * std::max(1.0, std::abs(expected)))
                      << what << ", tile " << tile << " texel " << c << ", " << r;
                }
              } else {
                const uint32_t wb = w * 2;
                // Per channel: the mean of the four below.
                const auto meanBelow = [&](const std::vector<glm::vec4>& texels, int channel) {
                  double sum = 0;
                  for (uint32_t i = 0; i < 4; ++i) {
                    sum += texels[size_t{2 * r + i / 2} * wb + 2 * c + i % 2][channel];
                  }
                  return sum * 0.25;
                };
                const glm::dvec2 mean(meanBelow(below, 2), meanBelow(below, 3));
                const glm::dvec2 squares(meanBelow(momentsBelow, 0), meanBelow(momentsBelow, 1));
                worstMean =
                    std::max({worstMean, std::abs(got.z - mean.x), std::abs(got.w - mean.y)});
                worstSecond = std::max({worstSecond, std::abs(gotSecond.x - squares.x),
                                        std::abs(gotSecond.y - squares.y)});
                ASSERT_NEAR(got.z, mean.x, 1e-3) << what << ", level " << level;
                ASSERT_NEAR(got.w, mean.y, 1e-3) << what << ", level " << level;
                ASSERT_NEAR(gotSecond.x, squares.x, 2e-3) << what << ", level " << level;
                ASSERT_NEAR(gotSecond.y, squares.y, 2e-3) << what << ", level " << level;
              }
              const uint32_t refW = referenceWidth >> level, refH = referenceHeight >> level;
              if (offsetX + c >= refW || offsetY + r >= refH) continue;
              ++compared;
              const size_t at = size_t{offsetY + r} * refW + offsetX + c;
              const glm::vec4 one = reference[at], oneSecond = referenceMoments[at];
              if (got.z != one.z || got.w != one.w || gotSecond.x != oneSecond.x ||
                  gotSecond.y != oneSecond.y) {
                ++different;
              }
            }
          }
        }
      }
      EXPECT_GT(compared, 0u) << what;
      EXPECT_EQ(different, 0u) << what << ": " << different << " of " << compared;
      std::printf(
          "%s: level 0 against decodeHorizon worst %.2g rad, levels above against the "
          "means below worst %.2g rad, %.2g rad^2\n",
          what.c_str(), worst, worstMean, worstSecond);
    }
    // The slopes themselves are what they were without horizons.
    const std::vector<glm::vec4> slopesAfter = readSlopes(device(), tiled.slopePages()[0], 7, 0);
    ASSERT_EQ(slopesAfter.size(), slopesBefore.size());
    for (size_t i = 0; i < slopesAfter.size(); ++i) {
      ASSERT_EQ(slopesAfter[i].x, slopesBefore[i].x) << i;
      ASSERT_EQ(slopesAfter[i].y, slopesBefore[i].y) << i;
    }
  }
}

// The horizon mode in a tiled scene: the horizons of the pair
// of directions beside the sun lie in the slope texture (engine/
// terrain_scene.h setHorizons), in the heights' tiles, read with the
// normal's fetch. 8-bit codes of 8 directions and 4-bit codes of 16, a sun
// 9 degrees up (the horizons hide it where the aperture's cap does not),
// from above and obliquely: the tolerance of
// TiledTexturesRenderAsOneImageInEveryMode.
TEST_F(TileRender, HorizonModeTiledAsOneImage) {
  const Heightfield field = fbm();
  const AlbedoImage colours = albedo();
  TerrainRenderer renderer(device(), kWidth, kHeight);
  for (const auto& [directions, bits] : {std::pair{8, 8}, std::pair{16, 4}}) {
    BakeOptions bake;
    bake.azimuths = 16;
    bake.horizons = true;
    bake.horizonDirections = directions;
    bake.horizonBits = bits;
    const BakeResult baked = bakeApertures(field, bake);
    TerrainScene single(device(), field, baked.aperture, &colours, 400000);
    TerrainScene tiled(device(), field, baked.aperture, &colours, 400000, {kTile, 0});
    ASSERT_EQ(tiled.tiles().tileCount(), 20u);
    const uint64_t singleBytes = single.textureBytes(), tiledBytes = tiled.textureBytes();
    single.setHorizons(device(), baked.horizons);
    tiled.setHorizons(device(), baked.horizons);
    ASSERT_TRUE(tiled.hasHorizons());
    // Device bytes: 4 more per texel of a tile image (core, border,
    // alignment) whatever the layout: B and A of the slopes.
    // 4 B of means in the slopes, 4 B of second moments, in each of 20 tiles.
    EXPECT_EQ(tiled.horizonBytes(), tiled.tiles().layerTexels() * 20 * 8);
    ASSERT_EQ(tiled.horizonMomentPages().size(), tiled.slopePages().size());
    EXPECT_EQ(tiled.horizonMomentPages()[0].desc().format, VK_FORMAT_R16G16_SFLOAT);
    EXPECT_EQ(tiled.textureBytes(), tiledBytes + tiled.horizonBytes());
    EXPECT_EQ(single.textureBytes(), singleBytes + single.horizonBytes());
    // The slopes with horizons take 8 bytes a texel in the heights' pages,
    // planned for 4: pages that hold ten heights' layers and no more refuse
    // them, and the scene stays as it was.
    const uint64_t pageBytes = 10 * tiled.tiles().layerTexels() * 4 * 16 / 15;
    TerrainScene smallPages(device(), field, baked.aperture, &colours, 400000, {kTile, pageBytes});
    ASSERT_EQ(smallPages.tiles().layersPerPageOf(TerrainTexture::Height), 10u);
    try {
      smallPages.setHorizons(device(), baked.horizons);
      ADD_FAILURE() << "horizons in pages of " << pageBytes << " B";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("do not fit one image"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(smallPages.hasHorizons());
    EXPECT_EQ(smallPages.slopePages()[0].desc().format, VK_FORMAT_R16G16_SFLOAT);
    std::printf(
        "%d directions of %d bits: horizons %llu B one tile (%.2f B per DEM texel), "
        "%llu B in 20 tiles (%.2f B per DEM texel)\n",
        directions, bits, static_cast<unsigned long long>(single.horizonBytes()),
        double(single.horizonBytes()) / (kWidth * kHeight),
        static_cast<unsigned long long>(tiled.horizonBytes()),
        double(tiled.horizonBytes()) / (kWidth * kHeight));
    // Suns at 230 degrees and 281.25: both scenes lay every tile's pair for
    // each (set for directions 0 and 1).
    for (const double sunAzimuth : {230.0, 281.25}) {
      for (const bool top : {true, false}) {
        FrameSettings s = top ? topView(ShadingMode::Horizon) : obliqueView(ShadingMode::Horizon);
        setSunAndSky(s.lighting, sunAzimuth, 9, 2.5);
        const FrameResult reference = renderer.render(single, s, false);
        const Difference d = compare(renderer.render(tiled, s, false), reference, top);
        char azimuth[16];
        std::snprintf(azimuth, sizeof azimuth, "%g", sunAzimuth);
        const std::string what = std::to_string(directions) + " directions of " +
                                 std::to_string(bits) + " bits, sun at " + azimuth +
                                 (top ? ", top" : ", oblique");
        EXPECT_EQ(tiled.horizonFirst(),
                  horizonPairFor(directions, sunAzimuthRad(s.lighting.sunDirection), -1))
            << what;
        EXPECT_NE(tiled.horizonFirst(), 0) << what;
        EXPECT_EQ(single.horizonFirst(), tiled.horizonFirst()) << what;
        expectTiledAsOneImage(d, what);
        // The horizons matter in this view: approx lights much that they hide.
        FrameSettings approx = s;
        approx.mode = ShadingMode::Approx;
        const Difference fromApprox =
            compare(renderer.render(single, approx, false), reference, top);
        EXPECT_GT(fromApprox.pixelsBeyondOne, size_t(kWidth * kHeight / 50)) << what;
      }
    }
  }
}

// The apertures alone in three pages, heights and albedo in one: the
// four-way aperture pick (terrain_aperture_pages4.frag). A 192 x 64 DEM in
// three 64-texel tiles; pages of 3.2 height layers hold three of them and
// one aperture layer.
TEST_F(TileRender, AperturesInSeveralPagesWithHeightsInOne) {
  SyntheticTerrainOptions o;
  o.width = 192;
  o.height = 64;
  o.cellSizeM = kCellM;
  o.featureSizeTexels = 32;
  const Heightfield field = makeSyntheticTerrain(o);
  BakeOptions bake;
  bake.azimuths = 16;
  const ApertureMap aperture = bakeApertures(field, bake).aperture;
  const TerrainScene single(device(), field, aperture, nullptr, 400000);
  TerrainTileLimits probe;
  probe.maxTileTexels = kTile;
  const uint64_t heightLayerBytes = planTerrainTiles(192, 64, probe).layerTexels() * 4;
  const TerrainScene tiled(device(), field, aperture, nullptr, 400000,
                           {kTile, heightLayerBytes * 32 / 10 * 16 / 15});
  const TerrainTileLayout& t = tiled.tiles();
  ASSERT_EQ(t.tileCount(), 3u);
  ASSERT_EQ(t.pagesOf(TerrainTexture::Height), 1u);
  ASSERT_EQ(t.pagesOf(TerrainTexture::Aperture), 3u);
  TerrainRenderer renderer(device(), 192, 64);
  for (const ShadingMode mode : {ShadingMode::Approx, ShadingMode::DebugBentNormal,
                                 ShadingMode::DebugVisible, ShadingMode::DebugSunFraction}) {
    FrameSettings s = lighting(mode);
    s.camera.position = {0, 0, 60000};
    s.camera.lookAt = {0, 0, 0};
    s.camera.verticalFovDeg = 2 * std::atan(0.5 * 64 * kCellM / 60000) * 180 / std::numbers::pi;
    const Difference d =
        compare(renderer.render(tiled, s, false), renderer.render(single, s, false), false);
    EXPECT_LE(d.pixelsOff, size_t(192 * 64 / 1000)) << int(mode);
    EXPECT_LE(d.maxLsb, 1) << int(mode);
  }
}

// A staged scene (aal-view's dropped DEMs) in 20 tiles: band by band, each
// share in a submission of its own, every tile's heights, levels and slopes
// arrive as a scene built at once makes them.
TEST_F(TileRender, AStagedSceneTilesAsOneBuiltAtOnce) {
  const Heightfield field = fbm();
  const TerrainScene atOnce(device(), field, nullptr, 400000, {kTile, 0});
  std::unique_ptr<TerrainScene> staged = TerrainScene::staged(
      device(), prepareTerrain(std::make_shared<const Heightfield>(field)), 400000, {kTile, 0});
  ASSERT_EQ(staged->tiles().tileCount(), 20u);
  int shares = 0;
  bool done = false;
  while (!done) {
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      done = staged->recordBuildShare(device(), cmd, 65536);
    });
    device().deletionQueue().releaseCompleted(device().deletionQueue().endFrame());
    ASSERT_LT(++shares, 100);
  }
  EXPECT_GE(shares, 3);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  for (const ShadingMode mode : {ShadingMode::Approx, ShadingMode::BaselineLambert}) {
    const FrameSettings s = obliqueView(mode);
    EXPECT_EQ(renderer.render(*staged, s, false).display, renderer.render(atOnce, s, false).display)
        << int(mode);
  }
}

// The open-sky scene (aal-view before the bake, the LOD benchmark) and a
// scene without an albedo image tile too.
TEST_F(TileRender, OpenSkySceneWithPaletteTiles) {
  const Heightfield field = fbm();
  const TerrainScene single(device(), field, nullptr, 400000);
  const TerrainScene tiled(device(), field, nullptr, 400000, {kTile, 0});
  ASSERT_EQ(tiled.tiles().tileCount(), 20u);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  const FrameSettings s = obliqueView(ShadingMode::Approx);
  const Difference d =
      compare(renderer.render(tiled, s, false), renderer.render(single, s, false), false);
  // As in every mode above: 1 LSB, but for the odd silhouette pixel (vertex
  // heights are mip fetches between texel centres, whose weights round
  // differently in a tile's smaller image).
  EXPECT_LE(d.pixelsOff, size_t(kWidth * kHeight / 1000));
  EXPECT_LE(d.pixelsBeyondOne, size_t(kWidth * kHeight / 10000));
  EXPECT_LE(d.maxBeyondEdge, 1);
}

}  // namespace
}  // namespace aal
