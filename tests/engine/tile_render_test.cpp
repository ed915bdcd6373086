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
#include <cmath>
#include <cstdio>
#include <string>

#include <glm/vec3.hpp>

#include "albedo_image.h"
#include "bake.h"
#include "sky_lighting.h"
#include "synthetic.h"
#include "terrain_renderer.h"
#include "terrain_scene.h"
#include "vulkan_test.h"

namespace aal {
namespace {

constexpr int kWidth = 300, kHeight = 200;  // DEM texels; the top view's pixels
constexpr double kCellM = 30.0;
constexpr uint32_t kTile = 64;  // forced: 5 x 4 tiles of 60 x 50 texels

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
  const SkyLighting light = makeSkyLighting(230, 25, 2.5);
  s.sunDirection = light.sunDirection;
  s.sunIrradiance = light.sunIrradiance;
  s.skyRadiance = light.skyRadiance;
  s.sky = light.sky;
  s.exposure = 0.07f;
  s.obscurance.radiusM = 400;  // about 13 texels: samples cross the seams
  return s;
}

// Straight down from high above: pixel (i, j) sees about texel (i, j).
FrameSettings topView(ShadingMode mode) {
  FrameSettings s = lighting(mode);
  s.camera.position = {0, 0, 60000};
  s.camera.lookAt = {0, 0, 0};
  s.camera.verticalFovDeg = 2 * std::atan(0.5 * kHeight * kCellM / 60000) * 180 / M_PI;
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
      const int sx = x % 60, sy = y % 50;
      const bool seam = std::min(sx, 60 - sx) <= 2 || std::min(sy, 50 - sy) <= 2;
      if (topViewSeams && seam) d.maxLsbAtSeams = std::max(d.maxLsbAtSeams, worst);
    }
  }
  return d;
}

class TileRender : public VulkanTest {};

TEST_F(TileRender, TiledTexturesRenderAsOneImageInEveryMode) {
  const Heightfield field = fbm();
  BakeOptions bake;
  bake.azimuths = 16;
  const ApertureMap aperture = bakeApertures(field, bake).aperture;
  const AlbedoImage colours = albedo();
  const TerrainScene single(device(), field, aperture, &colours, 400000);
  // Tile images of 64 x 54 texels: 13 824 bytes a layer of heights or
  // albedo, 27 648 of apertures; pages are filled to 15/16 of their bytes.
  const TerrainScene onePage(device(), field, aperture, &colours, 400000, {kTile, 0});
  // Heights and albedo: 20 layers in one page; apertures: 10 in each of two.
  const TerrainScene aperturePages(device(), field, aperture, &colours, 400000,
                                   {kTile, 20 * 13824 * 16 / 15});
  // Heights and albedo: 10 layers in each of two pages; apertures: 5 in four.
  const TerrainScene allPages(device(), field, aperture, &colours, 400000,
                              {kTile, 10 * 13824 * 16 / 15});
  ASSERT_EQ(single.tiles().tileCount(), 1u);
  ASSERT_EQ(onePage.tiles().tileCount(), 20u);
  ASSERT_EQ(onePage.tiles().coreWidth, 60u);
  ASSERT_EQ(onePage.tiles().coreHeight, 50u);
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
        std::printf("%s: max %d LSB (seams %d), %zu of %d pixels differ, %zu beyond 1 LSB\n",
                    what.c_str(), d.maxLsb, d.maxLsbAtSeams, d.pixelsOff, kWidth * kHeight,
                    d.pixelsBeyondOne);
        // Tolerance: 1 LSB of the 8-bit output (a fetch's coordinate rounds
        // differently in a tile's image: heights differ by ~1e-5 of a
        // texel's slope), none more at the seams, and a handful of pixels
        // (<= 0.01%) beyond it, each on an edge of the picture that explains
        // its difference.
        EXPECT_LE(d.maxLsbAtSeams, 1) << what;
        EXPECT_LE(d.pixelsOff, size_t(kWidth * kHeight / 1000)) << what;
        EXPECT_LE(d.pixelsBeyondOne, size_t(kWidth * kHeight / 10000)) << what;
        EXPECT_LE(d.maxBeyondEdge, 1) << what;
      }
    }
  }
}

// The apertures alone in three pages, heights and albedo in one: the
// four-way aperture pick (terrain_aperture_pages4.frag). A 192 x 64 DEM in
// three 64-texel tiles (images of 68 x 68: 18 496 bytes a layer of heights,
// 36 992 of apertures; pages of 55 500 bytes hold three and one).
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
  const TerrainScene tiled(device(), field, aperture, nullptr, 400000, {kTile, 59200});
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
    s.camera.verticalFovDeg = 2 * std::atan(0.5 * 64 * kCellM / 60000) * 180 / M_PI;
    const Difference d =
        compare(renderer.render(tiled, s, false), renderer.render(single, s, false), false);
    EXPECT_LE(d.pixelsOff, size_t(192 * 64 / 1000)) << int(mode);
    EXPECT_LE(d.maxLsb, 1) << int(mode);
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
  EXPECT_LE(d.maxLsb, 1);
}

}  // namespace
}  // namespace aal
