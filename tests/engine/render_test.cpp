// Headless renders under validation: physical checks and golden images.
#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/deletion_queue.h"
#include "aperture/engine/vk/serial_pass_timer.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/reference/relief.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

// A north-south ridge: z = 400 - 2 |x| (slopes of 63 degrees), 2 km square.
Heightfield ridge() {
  Heightfield f;
  f.width = f.height = 101;
  f.cellSizeXM = f.cellSizeYM = 20;
  f.z.resize(f.texelCount());
  for (int row = 0; row < f.height; ++row) {
    for (int col = 0; col < f.width; ++col) {
      const double x = (col - 50) * 20.0;
      f.z[f.index(col, row)] = static_cast<float>(std::max(0.0, 400.0 - 2.0 * std::abs(x)));
    }
  }
  return f;
}

// The apertures and directional horizons (8 directions of 8 bits) of `f`,
// baked from 64 azimuths: the horizon mode's scenes.
BakeResult bakeWithHorizons(const Heightfield& f) {
  BakeOptions o;
  o.azimuths = 64;
  o.horizons = true;
  return bakeApertures(f, o);
}

ApertureMap bake(const Heightfield& f) {
  BakeOptions o;
  o.azimuths = 64;
  return bakeApertures(f, o).aperture;
}

// Looking straight down from above: image x is east, image y is south.
FrameSettings topView(const Heightfield& f, ShadingMode mode, double sunAzimuthDeg,
                      double sunElevationDeg, float sunRadiusRad = kSunRadiusRad) {
  FrameSettings s;
  s.mode = mode;
  s.camera.position = {0, 0, 8000};
  s.camera.lookAt = {0, 0, 0};
  s.camera.verticalFovDeg =
      2 * std::atan(0.55 * (f.width - 1) * f.cellSizeXM / 8000) * 180 / std::numbers::pi;
  setSunAndSky(s.lighting, sunAzimuthDeg, sunElevationDeg, 2.5);
  s.lighting.sunRadiusRad = sunRadiusRad;
  s.lighting.exposure = 0.07f;
  return s;
}

float red(const FrameResult& frame, int x, int y) {
  return frame.linear[4 * (static_cast<size_t>(y) * frame.width + x)];
}

class Render : public VulkanTest {};

TEST_F(Render, LowWesternSunShadowsTheEastSlope) {
  const Heightfield f = ridge();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), 128, 128);
  // Sun in the west, 20 degrees up: the 63-degree east slope faces away.
  const FrameResult frame =
      renderer.render(scene, topView(f, ShadingMode::DebugSunFraction, 270, 20), true);
  // Pixels a quarter of the way from the centre to each side, mid-height.
  const float west = red(frame, 64 - 14, 64), east = red(frame, 64 + 14, 64);
  EXPECT_GT(west, 0.99f) << "west slope lit";
  EXPECT_LT(east, 0.01f) << "east slope in shadow";
  // And in the shaded image the lit side is brighter: the sun at 20 degrees
  // on flat ground adds a/pi E_sun sin 20 to the sky light both sides get
  // (2.7 times the shadowed side here; it read 3 times more while the Lambert
  // term was taken halfway between B and L, see terrain/light/caps.h).
  const FrameResult lit = renderer.render(scene, topView(f, ShadingMode::Approx, 270, 20), true);
  EXPECT_GT(red(lit, 64 - 14, 64), 2 * red(lit, 64 + 14, 64));
  // With the whole sun visible the direct light is the Lambert baseline's.
  const FrameResult lambert =
      renderer.render(scene, topView(f, ShadingMode::BaselineLambert, 270, 20), true);
  const float westSky = red(lit, 64 - 14, 64) - red(lambert, 64 - 14, 64);
  EXPECT_LT(westSky, 0.0f) << "the aperture takes sky away, never sun";
}

// The horizon mode: the plain 600 m east of the ridge sees its top
// 33.7 degrees up in the west. A sun in the west at 28 degrees is behind the
// ridge there; one cap per texel (approx) lets it through, the directional
// horizons do not. At 40 degrees both light it alike.
TEST_F(Render, HorizonModeShadowsThePlainBehindTheRidge) {
  const Heightfield f = ridge();
  const BakeResult baked = bakeWithHorizons(f);
  TerrainScene scene(device(), f, baked.aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), 128, 128);
  EXPECT_THROW(renderer.render(scene, topView(f, ShadingMode::Horizon, 270, 28), true),
               std::invalid_argument);
  scene.setHorizons(device(), baked.horizons);
  // Pixel 99 of 128 across 2200 m: 600 m east of the crest (29: 600 m west).
  const auto at = [&](ShadingMode mode, double elevation, int x) {
    FrameSettings s = topView(f, mode, 270, elevation);
    s.obscurance.enabled = false;
    return red(renderer.render(scene, s, true), x, 64);
  };
  const float approxLow = at(ShadingMode::Approx, 28, 99),
              horizonLow = at(ShadingMode::Horizon, 28, 99);
  EXPECT_LT(horizonLow, 0.5f * approxLow) << "behind the ridge: sky light only";
  EXPECT_NEAR(at(ShadingMode::Horizon, 28, 29), at(ShadingMode::Approx, 28, 29),
              0.02f * at(ShadingMode::Approx, 28, 29))
      << "the open plain west of the ridge sees the sun in both";
  EXPECT_NEAR(at(ShadingMode::Horizon, 40, 99), at(ShadingMode::Approx, 40, 99),
              0.02f * at(ShadingMode::Approx, 40, 99))
      << "above the ridge the sun is seen in both";
  // A horizon map of another size is refused.
  HorizonMap small = baked.horizons;
  small.width -= 1;
  small.codes.resize(size_t(small.width) * small.height * size_t(small.directions));
  EXPECT_THROW(scene.setHorizons(device(), small), std::invalid_argument);
}

// The horizon mode reads the right stored direction, through either place in
// the slope texture: the pair's first direction in B, its second in A
// (TerrainScene::setHorizons; 8- and 4-bit codes). Flat ground whose
// horizons are made up: every direction's horizon is 45 degrees or -2, in a
// pattern that no swap of two directions keeps; a sun 30 degrees up in each
// stored direction, and a fifth of a step to either side of it, must be
// hidden exactly where its direction's horizon is high. Each sun is drawn
// with the scene's pair laid as the sun's own, as the pair before it and as
// one far off first: the renderer keeps a pair that serves the sun (a sun on
// direction k is served by k-1, k and k, k+1), or re-lays; so every
// direction is read from B and from A.
TEST_F(Render, HorizonModeReadsEveryStoredDirection) {
  Heightfield f;
  f.width = f.height = 33;
  f.cellSizeXM = f.cellSizeYM = 20;
  f.z.assign(f.texelCount(), 100.0f);
  TerrainScene scene(device(), f, bake(f), nullptr, 100000);
  TerrainRenderer renderer(device(), 64, 64);
  for (const int bits : {8, 4}) {
    HorizonMap map;
    map.width = f.width;
    map.height = f.height;
    map.directions = 16;
    map.bits = bits;
    const auto high = [](int k) {
      constexpr bool kHigh[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 1, 0, 1};
      return kHigh[(k + 16) % 16];
    };
    for (size_t texel = 0; texel < f.texelCount(); ++texel) {
      for (int k = 0; k < map.directions; ++k) {
        map.codes.push_back(encodeHorizon(high(k) ? 0.7853982f : -0.0349066f, bits));
      }
    }
    scene.setHorizons(device(), map);
    for (int k = 0; k < map.directions; ++k) {
      bool readFrom[2] = {false, false};  // B (first of the pair), A (second)
      for (const double offset : {0.0, -0.2, 0.2}) {
        // Direction k is k * 22.5 degrees counter-clockwise from east: compass
        // 90 - that. A fifth of a step away the horizon is still high (above
        // 35 degrees) or low (below 8) as direction k's.
        FrameSettings s = topView(f, ShadingMode::BaselineLambert, 90.0 - 22.5 * (k + offset), 30);
        s.obscurance.enabled = false;
        const float lambert = red(renderer.render(scene, s, true), 32, 32);
        s.mode = ShadingMode::Horizon;
        for (const int laid : {k, (k + 15) % 16, (k + 8) % 16}) {
          scene.relayHorizons(device(), laid);
          const float lit = red(renderer.render(scene, s, true), 32, 32);
          const int used = scene.horizonFirst();
          const std::array<float, 2> w =
              horizonPairWeights(16, sunAzimuthRad(s.lighting.sunDirection), used);
          // The pair drawn with holds direction k and weighs it most.
          ASSERT_TRUE(used == k || (used + 1) % 16 == k) << k << " drawn with " << used;
          EXPECT_GE(w[used == k ? 0 : 1], 0.8f - 1e-5f) << k << " drawn with " << used;
          readFrom[used == k ? 0 : 1] = true;
          const std::string what = std::to_string(bits) + "-bit codes, direction " +
                                   std::to_string(k) + " " + std::to_string(offset) + ", laid " +
                                   std::to_string(laid) + ", drawn with " + std::to_string(used);
          if (high(k)) {
            EXPECT_LT(lit, 0.5f * lambert) << what << ": hidden";
          } else {
            EXPECT_GT(lit, 0.8f * lambert) << what << ": seen";
          }
        }
      }
      EXPECT_TRUE(readFrom[0] && readFrom[1]) << bits << "-bit codes, direction " << k;
    }
  }
}

// A re-lay spread over frames (FrameSettings::horizonRelayTexelsPerFrame,
// engine/horizon_relay.h): the ridge's horizons of 8 directions, a sun 26
// degrees up turning 2 degrees a frame across direction 3 (compass 315).
// The re-lay takes several frames; in each of them the picture is, byte for
// byte, that of a fresh scene holding a pair with the shared direction and
// drawn for the same sun, which reads that direction alone (the bound of
// docs/rendering.md); once it is done, within 1 of a fresh scene laid for the
// sun. One re-lay in all; a sun that then stays where it is re-lays no more.
TEST_F(Render, SpreadReLayDrawsTheSharedDirectionThenTheNewPair) {
  const Heightfield f = ridge();
  const BakeResult baked = bakeWithHorizons(f);
  const auto shared = std::make_shared<const HorizonMap>(baked.horizons);
  TerrainRenderer renderer(device(), 96, 96);
  const auto frameFor = [&](double compassDeg) {
    FrameSettings s = topView(f, ShadingMode::Horizon, compassDeg, 26);
    s.obscurance.enabled = false;
    s.horizonRelayTexelsPerFrame = 1;  // the least: one band a frame unless the sun hurries
    return s;
  };
  TerrainScene moving(device(), f, baked.aperture, nullptr, 100000);
  moving.setHorizons(device(), shared, 2);
  ASSERT_GE(moving.horizonBands(), 3u);
  uint32_t mixingFrames = 0, compared = 0;
  FrameResult last;
  double compass = 330;
  for (; compass >= 290; compass -= 2) {
    const FrameSettings s = frameFor(compass);
    last = renderer.render(moving, s, false);
    const HorizonChannels& c = moving.horizonChannels();
    if (!c.mixing()) continue;
    ++mixingFrames;
    const int sharedDirection = c.directions[1 - c.mixed];
    EXPECT_EQ(sharedDirection, 3);
    const float azimuth = sunAzimuthRad(s.lighting.sunDirection);
    const float off = horizonStepsFrom(8, azimuth, sharedDirection);
    ASSERT_LE(std::abs(off), horizonRelayReach(8) + 1e-6f) << compass;
    // A fresh scene and renderer (no motion seen): a pair that holds the
    // shared direction at its end nearest the sun keeps it and reads it alone.
    TerrainScene fresh(device(), f, baked.aperture, nullptr, 100000);
    fresh.setHorizons(device(), shared, off >= 0 ? sharedDirection - 1 : sharedDirection);
    TerrainRenderer reference(device(), 96, 96);
    const FrameResult expected = reference.render(fresh, s, false);
    EXPECT_EQ(fresh.horizonRelays(), 0u);
    EXPECT_EQ(last.display, expected.display) << "compass " << compass;
    ++compared;
  }
  EXPECT_GE(mixingFrames, 2u) << "spread over frames";
  EXPECT_EQ(compared, mixingFrames);
  EXPECT_FALSE(moving.horizonChannels().mixing());
  EXPECT_EQ(moving.horizonFirst(), 3);
  EXPECT_EQ(moving.horizonRelays(), 1u);

  const FrameSettings end = frameFor(compass + 2);
  TerrainScene fresh(device(), f, baked.aperture, nullptr, 100000);
  fresh.setHorizons(device(), shared,
                    horizonPairFor(8, sunAzimuthRad(end.lighting.sunDirection), -1));
  const FrameResult expected = renderer.render(fresh, end, false);
  ASSERT_EQ(last.display.size(), expected.display.size());
  int worst = 0;
  for (size_t i = 0; i < expected.display.size(); ++i) {
    worst = std::max(worst, std::abs(int(last.display[i]) - int(expected.display[i])));
  }
  EXPECT_LE(worst, 1) << "re-laid over frames against laid for the sun";

  // The sun stays: nothing more is written.
  for (int frame = 0; frame < 3; ++frame) renderer.render(moving, end, false);
  EXPECT_EQ(moving.horizonRelays(), 1u);
  EXPECT_FALSE(moving.horizonChannels().mixing());
}

// A sun that jumps to the opposite side in aal-view's spread policy: the
// new pair is laid a band a frame, both channels in place; every frame
// meanwhile is, byte for byte, the approx picture of the same sun (no band's
// horizons are read), and the frame that completes it and those after are a
// fresh scene's laid for that sun. One re-lay in all.
TEST_F(Render, SpreadJumpDrawsApproxWhileThePairIsLaidThenTheNewPair) {
  const Heightfield f = ridge();
  const BakeResult baked = bakeWithHorizons(f);
  const auto shared = std::make_shared<const HorizonMap>(baked.horizons);
  TerrainRenderer renderer(device(), 96, 96), reference(device(), 96, 96);
  const auto frameFor = [&](double compassDeg, ShadingMode mode) {
    FrameSettings s = topView(f, mode, compassDeg, 26);
    s.obscurance.enabled = false;
    s.horizonRelayTexelsPerFrame = 1;  // one band a frame
    return s;
  };
  TerrainScene moving(device(), f, baked.aperture, nullptr, 100000);
  const FrameSettings before = frameFor(330, ShadingMode::Horizon);
  moving.setHorizons(device(), shared,
                     horizonPairFor(8, sunAzimuthRad(before.lighting.sunDirection), -1));
  renderer.render(moving, before, false);
  ASSERT_EQ(moving.horizonRelays(), 0u);

  const FrameSettings jumped = frameFor(150, ShadingMode::Horizon);
  const int pair = horizonPairFor(8, sunAzimuthRad(jumped.lighting.sunDirection), -1);
  const std::vector<uint8_t> approx =
      reference.render(moving, frameFor(150, ShadingMode::Approx), false).display;
  uint32_t layingFrames = 0;
  FrameResult last;
  for (uint32_t frame = 0; frame <= moving.horizonBands(); ++frame) {
    last = renderer.render(moving, jumped, false);
    if (!moving.horizonChannels().layingPair()) break;
    ++layingFrames;
    EXPECT_EQ(moving.horizonChannels().laying, pair);
    EXPECT_EQ(last.display, approx) << "frame " << frame;
  }
  EXPECT_EQ(layingFrames + 1, moving.horizonBands()) << "one band a frame";
  EXPECT_FALSE(moving.horizonChannels().layingPair());
  EXPECT_EQ(moving.horizonFirst(), pair);
  EXPECT_EQ(moving.horizonRelays(), 1u);

  TerrainScene fresh(device(), f, baked.aperture, nullptr, 100000);
  fresh.setHorizons(device(), shared, pair);
  const std::vector<uint8_t> expected = reference.render(fresh, jumped, false).display;
  EXPECT_NE(expected, approx) << "the horizons show in this picture";
  EXPECT_EQ(last.display, expected) << "the frame that completes the pair";
  EXPECT_EQ(renderer.render(moving, jumped, false).display, expected);
  EXPECT_EQ(moving.horizonRelays(), 1u);
}

// One headless frame whose commands begin with `share` (as aal-view's
// frames begin with a share of a finished bake); `done`: what it returned.
std::vector<uint8_t> frameAfterShare(const Device& device, TerrainRenderer& renderer,
                                     const TerrainScene& scene, const FrameSettings& s,
                                     const std::function<bool(VkCommandBuffer)>& share,
                                     bool& done) {
  const size_t bytes = size_t{renderer.width()} * renderer.height() * 4;
  Buffer back(device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  submitAndWait(device, [&](VkCommandBuffer cmd) {
    done = share(cmd);
    renderer.record(cmd, scene, s, FrameOutput{});
    copyImageToBuffer(cmd, renderer.displayImage(), back);
  });
  DeletionQueue& deletions = device.deletionQueue();
  deletions.releaseCompleted(deletions.endFrame());
  std::vector<uint8_t> pixels(bytes);
  back.read(pixels.data(), pixels.size());
  return pixels;
}

// aal-view's dropped DEMs: a staged scene (TerrainScene::staged) is built a
// share a frame, each share recorded into the commands of a frame that draws
// another scene, which it leaves as it was; nothing draws it before the last
// share; then it draws as the same scene built at once, byte for byte.
TEST_F(Render, AStagedSceneIsBuiltAShareAFrameThenDrawsAsOneBuiltAtOnce) {
  const Heightfield f = ridge();
  TerrainRenderer renderer(device(), 96, 96);
  FrameSettings s = topView(f, ShadingMode::Approx, 250, 20);
  s.obscurance.enabled = false;
  const TerrainScene atOnce(device(), f, nullptr, 100000);
  const std::vector<uint8_t> before = renderer.render(atOnce, s, false).display;
  std::unique_ptr<TerrainScene> staged = TerrainScene::staged(
      device(), prepareTerrain(std::make_shared<const Heightfield>(f)), 100000);
  ASSERT_FALSE(staged->built());
  EXPECT_THROW(renderer.render(*staged, s, false), std::logic_error);
  // The heights and apertures to copy, then the slopes to compute.
  uint64_t left = staged->buildTexelsLeft();
  EXPECT_GE(left, 2 * uint64_t(f.texelCount()));
  // The least share: one band a frame.
  const auto share = [&](VkCommandBuffer cmd) {
    return staged->recordBuildShare(device(), cmd, 1);
  };
  int shares = 0;
  bool done = false;
  while (!done) {
    EXPECT_EQ(frameAfterShare(device(), renderer, atOnce, s, share, done), before)
        << "share " << shares;
    ++shares;
    ASSERT_LT(shares, 100);
    if (done) break;
    EXPECT_FALSE(staged->built());
    EXPECT_LT(staged->buildTexelsLeft(), left) << "share " << shares;
    left = staged->buildTexelsLeft();
  }
  EXPECT_GE(shares, 4) << "spread over frames";
  EXPECT_TRUE(staged->built());
  EXPECT_EQ(staged->buildTexelsLeft(), 0u);
  EXPECT_TRUE(staged->recordBuildShare(device(), VK_NULL_HANDLE, 1)) << "nothing left to send";
  EXPECT_EQ(staged->textureBytes(), atOnce.textureBytes());
  EXPECT_EQ(staged->minHeight(), atOnce.minHeight());
  EXPECT_EQ(staged->maxHeight(), atOnce.maxHeight());
  EXPECT_NE(staged->id(), atOnce.id());
  // The slopes (the normals) and the heights, in every mode that reads them.
  for (const ShadingMode mode :
       {ShadingMode::Approx, ShadingMode::BaselineLambert, ShadingMode::DebugBentNormal}) {
    FrameSettings m = topView(f, mode, 250, 20);
    m.obscurance.enabled = false;
    EXPECT_EQ(renderer.render(*staged, m, false).display, renderer.render(atOnce, m, false).display)
        << int(mode);
  }
  FrameSettings oblique = s;
  oblique.camera.position = {-2500, -2500, 1500};
  EXPECT_EQ(renderer.render(*staged, oblique, false).display,
            renderer.render(atOnce, oblique, false).display);
}

// aal-view's background bake: the map staged into a scene that drew an open
// sky (TerrainScene::stageAperture) goes to the device a share a frame, each
// share recorded into the frame's own commands ahead of its passes. Until
// the last share every frame is, byte for byte, the open sky's picture; the
// frame of the last share and those after are a fresh scene's with the map;
// the scene's id changes with it.
TEST_F(Render, StagedApertureArrivesAShareAFrameThenDrawsAsAFreshScene) {
  const Heightfield f = ridge();
  const ApertureMap map = bake(f);
  TerrainRenderer renderer(device(), 96, 96);
  FrameSettings s = topView(f, ShadingMode::Approx, 90, 20);
  s.obscurance.enabled = false;
  TerrainScene arriving(device(), f, nullptr, 100000);
  // The least share: one band a frame.
  const auto share = [&](VkCommandBuffer cmd) { return arriving.recordApertureShare(cmd, 1); };

  const std::vector<uint8_t> openSky = renderer.render(arriving, s, false).display;
  EXPECT_THROW(arriving.stageAperture(device(), HalfApertureMap{.width = 3, .height = 3}),
               std::invalid_argument);
  EXPECT_FALSE(arriving.apertureStaged());
  arriving.stageAperture(device(), toHalfApertureMap(map));
  ASSERT_TRUE(arriving.apertureStaged());
  const uint64_t id = arriving.id();
  uint64_t left = arriving.apertureTexelsLeft();
  EXPECT_GE(left, uint64_t(f.texelCount()));
  int shares = 0;
  bool done = false;
  std::vector<uint8_t> last;
  while (!done) {
    last = frameAfterShare(device(), renderer, arriving, s, share, done);
    ++shares;
    ASSERT_LT(shares, 100);
    if (done) break;
    EXPECT_LT(arriving.apertureTexelsLeft(), left) << "share " << shares;
    left = arriving.apertureTexelsLeft();
    EXPECT_EQ(last, openSky) << "share " << shares << " drew a map not yet whole";
    EXPECT_EQ(arriving.id(), id);
  }
  EXPECT_GE(shares, 3) << "spread over frames";
  EXPECT_FALSE(arriving.apertureStaged());
  EXPECT_EQ(arriving.apertureTexelsLeft(), 0u);
  EXPECT_NE(arriving.id(), id);

  TerrainScene fresh(device(), f, map, nullptr, 100000);
  const std::vector<uint8_t> expected = renderer.render(fresh, s, false).display;
  EXPECT_NE(expected, openSky) << "the map shows in this picture";
  EXPECT_EQ(last, expected) << "the last share's frame";
  EXPECT_EQ(frameAfterShare(device(), renderer, arriving, s, share, done), expected);
  EXPECT_TRUE(done) << "nothing staged";
}

// The bake's horizons follow the same way (TerrainScene::stageHorizons): a
// band or more a frame into images of their own. Until the last share the
// scene has no horizons and draws `approx` as before, byte for byte; then
// it holds the pair it was staged with and draws both modes as a scene given
// that pair by setHorizons.
TEST_F(Render, StagedHorizonsArriveAShareAFrameThenDrawAsSetHorizons) {
  const Heightfield f = ridge();
  const BakeResult baked = bakeWithHorizons(f);
  const auto shared = std::make_shared<const HorizonMap>(baked.horizons);
  TerrainRenderer renderer(device(), 96, 96);
  FrameSettings horizon = topView(f, ShadingMode::Horizon, 292.5, 26);
  horizon.obscurance.enabled = false;
  FrameSettings approx = horizon;
  approx.mode = ShadingMode::Approx;
  const int first = horizonPairFor(8, sunAzimuthRad(horizon.lighting.sunDirection), -1);
  TerrainScene arriving(device(), f, baked.aperture, nullptr, 100000);
  const auto share = [&](VkCommandBuffer cmd) {
    return arriving.recordHorizonShare(device(), cmd, 1);
  };

  const std::vector<uint8_t> before = renderer.render(arriving, approx, false).display;
  HorizonMap small = baked.horizons;
  small.width = 7;
  EXPECT_THROW(arriving.stageHorizons(device(), std::make_shared<const HorizonMap>(small), first),
               std::invalid_argument);
  EXPECT_FALSE(arriving.horizonsStaged());
  arriving.stageHorizons(device(), shared, first);
  ASSERT_TRUE(arriving.horizonsStaged());
  EXPECT_FALSE(arriving.hasHorizons());
  ASSERT_GE(arriving.horizonBands(), 3u);
  uint32_t shares = 0;
  bool done = false;
  while (!done) {
    const std::vector<uint8_t> frame =
        frameAfterShare(device(), renderer, arriving, approx, share, done);
    ++shares;
    ASSERT_LE(shares, arriving.horizonBands());
    if (done) break;
    EXPECT_FALSE(arriving.hasHorizons()) << "share " << shares;
    EXPECT_EQ(frame, before) << "share " << shares;
  }
  EXPECT_EQ(shares, arriving.horizonBands()) << "one band a share";
  EXPECT_FALSE(arriving.horizonsStaged());
  ASSERT_TRUE(arriving.hasHorizons());
  EXPECT_EQ(arriving.horizonFirst(), first);
  EXPECT_EQ(arriving.horizonRelays(), 0u);

  TerrainScene fresh(device(), f, baked.aperture, nullptr, 100000);
  fresh.setHorizons(device(), shared, first);
  EXPECT_EQ(arriving.textureBytes(), fresh.textureBytes());
  const std::vector<uint8_t> expected = renderer.render(fresh, horizon, false).display;
  EXPECT_NE(expected, renderer.render(fresh, approx, false).display)
      << "the horizons show in this picture";
  EXPECT_EQ(renderer.render(arriving, horizon, false).display, expected);
  EXPECT_EQ(renderer.render(arriving, approx, false).display,
            renderer.render(fresh, approx, false).display);
  EXPECT_EQ(arriving.horizonRelays(), 0u);
}

// Re-laying the horizons for another sun (TerrainScene::relayHorizons, from
// TerrainRenderer::record) leaves the scene as a fresh one laid for that
// sun: the ridge's horizons of 8 directions, a sun in the west-north-west
// (between directions 3 and 4), then in the north-north-east (between 1 and
// 2), and back; the last picture equals, byte for byte, one from a scene
// given the horizons for that sun.
TEST_F(Render, ReLaidHorizonsDrawAsAFreshScene) {
  const Heightfield f = ridge();
  const BakeResult baked = bakeWithHorizons(f);
  ASSERT_EQ(baked.horizons.directions, 8);
  const auto shared = std::make_shared<const HorizonMap>(baked.horizons);
  TerrainRenderer renderer(device(), 128, 128);
  // Compass 292.5 degrees: 157.5 counter-clockwise from east, direction 3.5.
  FrameSettings west = topView(f, ShadingMode::Horizon, 292.5, 26);
  FrameSettings north = topView(f, ShadingMode::Horizon, 22.5, 26);
  west.obscurance.enabled = north.obscurance.enabled = false;
  ASSERT_EQ(horizonPairFor(8, sunAzimuthRad(west.lighting.sunDirection), -1), 3);
  ASSERT_EQ(horizonPairFor(8, sunAzimuthRad(north.lighting.sunDirection), 3), 1);

  TerrainScene moving(device(), f, baked.aperture, nullptr, 100000);
  moving.setHorizons(device(), shared);
  EXPECT_EQ(moving.horizonFirst(), 0);
  renderer.render(moving, west, false);
  EXPECT_EQ(moving.horizonFirst(), 3);
  renderer.render(moving, west, false);  // the same sun: no re-lay
  EXPECT_EQ(moving.horizonRelays(), 1u);
  renderer.render(moving, north, false);
  EXPECT_EQ(moving.horizonFirst(), 1);
  const FrameResult last = renderer.render(moving, west, false);
  EXPECT_EQ(moving.horizonFirst(), 3);
  EXPECT_EQ(moving.horizonRelays(), 3u);

  TerrainScene fresh(device(), f, baked.aperture, nullptr, 100000);
  fresh.setHorizons(device(), shared, 3);
  const FrameResult reference = renderer.render(fresh, west, false);
  EXPECT_EQ(fresh.horizonRelays(), 0u);
  EXPECT_EQ(last.display, reference.display) << "re-laid against laid for the sun";

  // The horizons matter in this picture: the plain east of the ridge is in
  // its shadow, which approx's cap lets the sun through.
  FrameSettings approx = west;
  approx.mode = ShadingMode::Approx;
  const FrameResult approxFrame = renderer.render(fresh, approx, false);
  size_t differing = 0;
  for (size_t i = 0; i < reference.display.size(); ++i) {
    differing += std::abs(int(reference.display[i]) - int(approxFrame.display[i])) > 8;
  }
  EXPECT_GT(differing, reference.display.size() / 40) << "horizon against approx";
}

TEST_F(Render, ShadowsSoftenAsTheSunGrows) {
  const Heightfield f = ridge();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), 128, 128);
  auto penumbraPixels = [&](float sunRadiusRad) {
    // Sun just above the east slope's horizon: the plains east of the ridge
    // see it through the edge of their apertures.
    const FrameResult frame = renderer.render(
        scene, topView(f, ShadingMode::DebugSunFraction, 270, 60, sunRadiusRad), true);
    int count = 0;
    for (uint32_t i = 0; i < frame.width * frame.height; ++i) {
      const float v = frame.linear[4 * i];
      if (v > 0.02f && v < 0.98f) ++count;
    }
    return count;
  };
  const int sharp = penumbraPixels(0.0047f), soft = penumbraPixels(0.08f);
  EXPECT_GT(soft, 2 * std::max(sharp, 1)) << "sharp " << sharp << " soft " << soft;
}

// Columns of a w x h render with a base (`withBase`) in which, below the
// lowest terrain pixel of the same view without it (`plain`), the opaque
// pixels are not one run: sky shows between the terrain and the base.
int skyGapColumns(const FrameResult& plain, const FrameResult& withBase, uint32_t w, uint32_t h) {
  const auto alpha = [&](const FrameResult& r, uint32_t x, uint32_t y) {
    return r.display[4 * (size_t{y} * w + x) + 3];
  };
  int gaps = 0;
  for (uint32_t x = 0; x < w; ++x) {
    int lowestTerrain = -1;
    for (uint32_t y = 0; y < h; ++y) {
      if (alpha(plain, x, y) > 0) lowestTerrain = int(y);
    }
    if (lowestTerrain < 0) continue;
    bool ended = false;
    for (uint32_t y = uint32_t(lowestTerrain); y < h; ++y) {
      if (alpha(withBase, x, y) == 0) {
        ended = true;
      } else if (ended) {
        ++gaps;
        break;
      }
    }
  }
  return gaps;
}

// --base: the solid base's walls hang from the DEM's edge down to
// `depth` below its lowest point, shaded as a Lambertian wall lit by the sun
// and half the sky (docs/rendering.md, "Solid base"): at the middle of the
// south wall (facing the sun) and of the east wall (sky only) the display
// value equals the closed form within 2/255; the terrain's own pixels do not
// change; in every column the terrain and the base below it are one run of
// opaque pixels (no sky between them), at the default LOD error and with
// level 0 at the edge: the walls hang from the terrain's own edge vertices;
// a deeper base covers more pixels; with the obscurance targets too.
TEST_F(Render, SolidBaseHangsFromTheEdgeAndIsShadedAsAWall) {
  SyntheticTerrainOptions o;
  o.width = o.height = 96;
  o.cellSizeM = 30;
  o.featureSizeTexels = 24;
  o.amplitudeM = 200;
  const Heightfield f = makeSyntheticTerrain(o);
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  constexpr uint32_t kW = 160, kH = 120;
  TerrainRenderer renderer(device(), kW, kH);
  const float zMin = *std::min_element(f.z.begin(), f.z.end());
  for (const auto& [obscurance, finest] :
       {std::pair{false, false}, std::pair{true, false}, std::pair{false, true}}) {
    FrameSettings s = topView(f, ShadingMode::Approx, 180, 30);  // sun due south, 30° up
    s.obscurance.enabled = obscurance;
    if (finest) s.lod.maxErrorPixels = 1e-3;
    s.transparentBackground = true;
    s.camera = framingCamera(demExtentM(f), zMin - 600.0, zMin + 400.0, double(kW) / kH, 135, 20);
    const FrameResult plain = renderer.render(scene, s, false);
    s.base = FrameSettings::Base{300.0f, glm::vec3(0.5f, 0.4f, 0.3f)};
    const FrameResult shallow = renderer.render(scene, s, false);
    s.base->depthM = 600.0f;
    const FrameResult deep = renderer.render(scene, s, false);
    const auto alpha = [&](const FrameResult& r, uint32_t x, uint32_t y) {
      return r.display[4 * (size_t{y} * kW + x) + 3];
    };
    size_t plainCount = 0, shallowCount = 0, deepCount = 0, changed = 0;
    for (uint32_t y = 0; y < kH; ++y) {
      for (uint32_t x = 0; x < kW; ++x) {
        plainCount += alpha(plain, x, y) > 0;
        shallowCount += alpha(shallow, x, y) > 0;
        deepCount += alpha(deep, x, y) > 0;
        if (alpha(plain, x, y) > 0) {
          ASSERT_GT(alpha(deep, x, y), 0) << x << " " << y;
          for (int c = 0; c < 3; ++c) {
            const size_t i = 4 * (size_t{y} * kW + x) + c;
            changed += plain.display[i] != deep.display[i];
          }
        }
      }
    }
    EXPECT_GT(shallowCount, plainCount + kW) << obscurance;
    EXPECT_GT(deepCount, shallowCount + kW) << obscurance;
    // The terrain's own pixels keep their colour but for rounding: the base
    // deepens the depth range, so the projection changes in its last bits
    // (measured: no channel value changed at the default error, 5 by one
    // step with level 0 at the edge, none of them at the edge).
    EXPECT_LE(changed, 3u * 3) << obscurance;
    // No sky between the terrain and the base: in every column, from the
    // lowest terrain pixel down, the opaque pixels are one run (above it
    // rough terrain may show sky between peaks, which is not the base's
    // business).
    const int gaps = skyGapColumns(plain, deep, kW, kH);
    // The wall's top is the terrain's edge, vertex for vertex, at any level
    // of detail (shaders/base_vertex.glsl): no gap (before the walls hung
    // from the level-0 edge, 3 of 160 columns showed a pixel of sky at the
    // default error).
    EXPECT_EQ(gaps, 0) << obscurance;
    std::printf(
        "base (obscurance %d, level 0 at the edge %d): %zu terrain channel values "
        "changed, %d columns with sky between terrain and base\n",
        int(obscurance), int(finest), changed, gaps);
    // The closed form at the middle of the south and east walls, 30 % of
    // the way down from the lowest edge height.
    const glm::dvec2 e = demExtentM(f);
    const double bottom = zMin - 600.0;
    const glm::mat4 m = projectionMatrix(s.camera, double(kW) / kH,
                                         depthRangeFor(s.camera, e, bottom, zMin + 400.0)) *
                        viewMatrix(s.camera);
    const glm::vec3 albedo = s.base->albedo;
    for (const auto& [point, normal] :
         {std::pair{glm::dvec3(0.0, -0.5 * e.y, zMin - 180.0), glm::vec3(0, -1, 0)},
          std::pair{glm::dvec3(0.5 * e.x, 0.0, zMin - 180.0), glm::vec3(1, 0, 0)}}) {
      const glm::vec4 clip = m * glm::vec4(glm::vec3(point), 1.0f);
      const int px = int((clip.x / clip.w * 0.5f + 0.5f) * kW);
      const int py = int((clip.y / clip.w * 0.5f + 0.5f) * kH);
      ASSERT_TRUE(px >= 0 && px < int(kW) && py >= 0 && py < int(kH)) << px << " " << py;
      const glm::vec3 irradiance =
          s.lighting.sunIrradiance * std::max(0.0f, glm::dot(normal, s.lighting.sunDirection)) +
          float(std::numbers::pi) * s.lighting.skyRadiance * 0.5f;
      const glm::vec3 expected =
          toneMap(albedo / float(std::numbers::pi) * irradiance, s.lighting.exposure);
      for (int c = 0; c < 3; ++c) {
        const int got = deep.display[4 * (size_t(py) * kW + px) + c];
        EXPECT_NEAR(got, 255.0f * expected[c], 2.0f)
            << "wall facing " << normal.x << "," << normal.y << " channel " << c << obscurance;
      }
      EXPECT_EQ(alpha(deep, px, py), 255);
    }
  }
}

// The walls meet the terrain's edge from every side, at fine and coarse
// levels of detail (morphing patches), on a DEM whose size is no multiple of
// the patches (their overhang folds onto the southern and eastern edges, and
// whole quadrants lie beyond them): no column shows sky between terrain and
// base.
TEST_F(Render, SolidBaseMeetsTheTerrainEdgeFromEveryView) {
  SyntheticTerrainOptions o;
  o.width = 130;
  o.height = 77;
  o.cellSizeM = 30;
  o.featureSizeTexels = 20;
  o.amplitudeM = 250;
  const Heightfield f = makeSyntheticTerrain(o);
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  constexpr uint32_t kW = 160, kH = 120;
  TerrainRenderer renderer(device(), kW, kH);
  const float zMin = *std::min_element(f.z.begin(), f.z.end());
  int views = 0, worst = 0;
  for (double lodError : {0.0, 6.0}) {
    for (double elevation : {12.0, 35.0}) {
      for (double azimuth = 10.0; azimuth < 360.0; azimuth += 45.0) {
        FrameSettings s = topView(f, ShadingMode::Approx, 180, 40);
        s.transparentBackground = true;
        if (lodError > 0.0) s.lod.maxErrorPixels = lodError;
        s.camera = framingCamera(demExtentM(f), zMin - 500.0, zMin + 500.0, double(kW) / kH,
                                 azimuth, elevation);
        const FrameResult plain = renderer.render(scene, s, false);
        s.base = FrameSettings::Base{500.0f, glm::vec3(0.5f, 0.4f, 0.3f)};
        const FrameResult withBase = renderer.render(scene, s, false);
        const int gaps = skyGapColumns(plain, withBase, kW, kH);
        EXPECT_EQ(gaps, 0) << "azimuth " << azimuth << " elevation " << elevation << " LOD error "
                           << lodError;
        worst = std::max(worst, gaps);
        ++views;
      }
    }
  }
  std::printf(
      "base on a 130 x 77 DEM: %d views, most columns with sky between terrain and base %d\n",
      views, worst);
}

TEST_F(Render, JacksboroRendersTerrainAndSky) {
  const Heightfield f =
      loadDem((fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif").string());
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 200000);
  TerrainRenderer renderer(device(), 160, 90);
  FrameSettings s = topView(f, ShadingMode::Approx, 135, 40);
  s.camera = defaultCamera(f, 160.0 / 90.0);
  const FrameResult frame = renderer.render(scene, s, false);
  // Not a blank image: the terrain differs from the sky and has texture.
  int minLuma = 255, maxLuma = 0;
  for (size_t i = 0; i < frame.display.size(); i += 4) {
    const int luma = (frame.display[i] + frame.display[i + 1] + frame.display[i + 2]) / 3;
    minLuma = std::min(minLuma, luma);
    maxLuma = std::max(maxLuma, luma);
  }
  EXPECT_GT(maxLuma - minLuma, 40);
  // The quadtree LOD draws what 160x90 pixels need (quads of about a pixel),
  // within the scene's budget.
  EXPECT_GT(frame.triangles, 0u);
  EXPECT_LE(frame.triangles, 200000u);
  // sky table, terrain, sky, obscurance, obscurance filter, composite (which
  // writes the display values: no tone-map pass).
  std::vector<std::string> passes;
  for (const auto& [name, ms] : frame.passMilliseconds) passes.push_back(name);
  EXPECT_EQ(passes, (std::vector<std::string>{"sky table", "terrain", "sky", "obscurance",
                                              "obscurance filter", "composite"}));
}

// The profiled frame (each step submitted on its own: aal-render
// --pass-profile) is the same frame: the same steps in order, the same
// picture to the bit, and every step's time measured. With obscurance off
// the terrain pass writes the display values and the obscurance steps go.
TEST_F(Render, AProfiledFrameSubmitsEachStepAloneAndDrawsTheSamePicture) {
  const Heightfield f = ridge();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 200000);
  TerrainRenderer renderer(device(), 96, 64);
  FrameSettings s = topView(f, ShadingMode::Approx, 250, 12);
  for (const bool obscurance : {true, false}) {
    s.obscurance.enabled = obscurance;
    const FrameResult frame = renderer.render(scene, s, false);
    const std::vector<SerialPassTimer::Step> steps = renderer.profile(scene, s, true);
    // What the profiled frame left in the display image.
    Buffer readback(device(), frame.display.size(), VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                    MemoryIntent::Readback);
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      copyImageToBuffer(cmd, renderer.displayImage(), readback);
    });
    std::vector<uint8_t> profiled(frame.display.size());
    readback.read(profiled.data(), profiled.size());
    EXPECT_TRUE(profiled == frame.display) << "obscurance " << obscurance;

    std::vector<std::string> names;
    for (const SerialPassTimer::Step& step : steps) {
      names.push_back(step.name);
      EXPECT_GE(step.wallMs, 0.0) << step.name;
      EXPECT_GE(step.cpuMs, 0.0) << step.name;
    }
    const std::vector<std::string> expected =
        obscurance ? std::vector<std::string>{"prepare (host)",
                                              "sky table",
                                              "terrain + sky (G-buffer)",
                                              "obscurance",
                                              "obscurance filter",
                                              "composite",
                                              "display hand-over, recording"}
                   : std::vector<std::string>{"prepare (host)", "sky table", "terrain + sky",
                                              "display hand-over, recording"};
    EXPECT_EQ(names, expected);
    // The terrain's shading is where the work is: its step is the longest
    // of the device's (the sky table is 64 x 32 texels).
    EXPECT_GT(steps[2].wallMs, steps[1].wallMs);
    const std::vector<SerialPassTimer::Step> whole = renderer.profile(scene, s, false);
    ASSERT_EQ(whole.size(), 1u);
    EXPECT_EQ(whole[0].name, "frame in one submission");
    EXPECT_GT(whole[0].wallMs, 0.0);
  }
}

// Golden images (tests/golden/), compared pixel by pixel on RGB (the alpha
// channel is a constant 1 and would only dilute an error). Lavapipe renders
// them bit for bit alike from run to run (docs/rendering.md, "Tests"); the
// 2/255 per channel are for another CPU or LLVM rounding floats differently:
// a step where the 8-bit value rounds, another where a half-float target
// (the obscurance passes' HDR colour) does. A changed picture fails; no mean
// or share of pixels lets it through. Only AAL_ACCEPT_GOLDENS=1 overwrites
// the golden (scripts/accept-goldens.sh, after review); on failure the render
// and a difference image are written next to the test binary.
constexpr int kGoldenTolerance = 2;  // per channel, out of 255

void expectMatchesGolden(const FrameResult& frame, const std::string& name) {
  const fs::path golden = fs::path(AAL_TEST_SOURCE_DIR) / "tests" / "golden" / (name + ".png");
  const fs::path actual = fs::path(AAL_TEST_OUTPUT_DIR) / (name + ".actual.png");
  const fs::path diff = fs::path(AAL_TEST_OUTPUT_DIR) / (name + ".diff.png");
  fs::remove(actual);
  fs::remove(diff);
  const char* accept = std::getenv("AAL_ACCEPT_GOLDENS");
  if (accept && std::string(accept) == "1") {
    writeFrame(golden.string(), frame);
    std::printf("accepted %s\n", golden.c_str());
    return;
  }
  if (accept) std::printf("AAL_ACCEPT_GOLDENS=%s: comparing (only 1 accepts)\n", accept);
  OIIO::ImageBuf expected(golden.string());
  ASSERT_TRUE(expected.read(0, 0, true, OIIO::TypeDesc::UINT8))
      << "missing golden " << golden << " (run scripts/accept-goldens.sh)";
  const int width = static_cast<int>(frame.width), height = static_cast<int>(frame.height);
  ASSERT_EQ(expected.spec().width, width) << golden;
  ASSERT_EQ(expected.spec().height, height) << golden;
  ASSERT_GE(expected.spec().nchannels, 3) << golden;
  std::vector<uint8_t> want(static_cast<size_t>(width) * height * 3);
  ASSERT_TRUE(expected.get_pixels(OIIO::ROI(0, width, 0, height, 0, 1, 0, 3), OIIO::TypeDesc::UINT8,
                                  want.data()));
  // The difference image: the largest channel difference as grey, 1/255
  // showing as 32/255, and the pixels beyond the tolerance red.
  std::vector<uint8_t> diffImage(static_cast<size_t>(width) * height * 4, 255);
  int failing = 0, worst = 0, worstX = 0, worstY = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        d = std::max(d, std::abs(frame.display[4 * i + c] - want[3 * i + c]));
      }
      if (d > worst) std::tie(worst, worstX, worstY) = std::tuple(d, x, y);
      failing += d > kGoldenTolerance;
      const uint8_t grey = static_cast<uint8_t>(std::min(255, 32 * d));
      diffImage[4 * i] = d > kGoldenTolerance ? 255 : grey;
      diffImage[4 * i + 1] = diffImage[4 * i + 2] = d > kGoldenTolerance ? 0 : grey;
    }
  }
  if (failing > 0) {
    writeFrame(actual.string(), frame);
    FrameResult difference;
    difference.width = frame.width;
    difference.height = frame.height;
    difference.display = std::move(diffImage);
    writeFrame(diff.string(), difference);
    ADD_FAILURE() << name << ": " << failing << " of " << width * height
                  << " pixels differ by more than " << kGoldenTolerance << "/255 from " << golden
                  << ", at most " << worst << "/255 (pixel " << worstX << "," << worstY
                  << "); the render is " << actual << ", the difference " << diff
                  << " (red: beyond the tolerance)";
  }
}

TEST_F(Render, GoldenRidgeAtDusk) {
  const Heightfield f = ridge();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), 96, 96);
  FrameSettings s = topView(f, ShadingMode::Approx, 250, 12);
  s.camera.position = {1500, -1800, 1200};
  s.camera.verticalFovDeg = 50;
  // A golden of the shading: the mesh within a pixel of the DEM's (at 96 x
  // 96 the default 4 pixels of geometric error lower the 63 degree crest
  // visibly; the LOD's own picture error is tested in lod_quality_test.cpp).
  s.lod.maxErrorPixels = 1;
  expectMatchesGolden(renderer.render(scene, s, false), "ridge-dusk");
}

TEST_F(Render, GoldenFbmDebugViews) {
  SyntheticTerrainOptions o;
  o.width = o.height = 64;
  o.featureSizeTexels = 24;
  const Heightfield f = makeSyntheticTerrain(o);
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), 64, 64);
  expectMatchesGolden(renderer.render(scene, topView(f, ShadingMode::DebugVisible, 0, 45), false),
                      "fbm-visible");
  expectMatchesGolden(
      renderer.render(scene, topView(f, ShadingMode::DebugBentNormal, 0, 45), false),
      "fbm-bent-normal");
}

// O and W (docs/design.md §6) of the same terrain, with an orange albedo so
// that the colour bleeding shows in W.
TEST_F(Render, GoldenFbmObscuranceAndTransfer) {
  SyntheticTerrainOptions o;
  o.width = o.height = 64;
  o.featureSizeTexels = 24;
  o.ridged = true;
  const Heightfield f = makeSyntheticTerrain(o);
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), 64, 64);
  FrameSettings s = topView(f, ShadingMode::DebugObscurance, 0, 45);
  s.obscurance.radiusM = 600;
  s.albedoValue = glm::vec3(0.8f, 0.5f, 0.2f);
  expectMatchesGolden(renderer.render(scene, s, false), "fbm-obscurance");
  s.mode = ShadingMode::DebugTransfer;
  expectMatchesGolden(renderer.render(scene, s, false), "fbm-transfer");
}

}  // namespace
}  // namespace aal
