// Where the renderer's frame goes and what was folded into fewer passes
// (engine/terrain_renderer.h FrameOutput): display values written
// by the last pass equal the tone-mapped linear frame; the sky from its
// table (shaders/sky_lut.glsl) equals the clear-sky model; a frame drawn
// straight into another image (a swapchain image) equals the headless one;
// a frame drawn at a reduced resolution is the smaller picture scaled up.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <tuple>

#include <glm/matrix.hpp>

#include "aperture/engine/supersampling.h"
#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/frames_in_flight.h"
#include "aperture/engine/vk/image.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/sky_model.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/terrain/view/quadtree_lod.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr uint32_t kWidth = 192, kHeight = 108;

// An fBm DEM of 30 m cells; the larger one's mesh a 1280x720 view draws
// coarser at 4 px of error than at 2.
Heightfield fbm(int size = 96, double featureTexels = 24, double amplitudeM = 300) {
  SyntheticTerrainOptions o;
  o.width = o.height = size;
  o.cellSizeM = 30;
  o.featureSizeTexels = featureTexels;
  o.amplitudeM = amplitudeM;
  return makeSyntheticTerrain(o);
}

ApertureMap bake(const Heightfield& f) {
  BakeOptions o;
  o.azimuths = 16;
  return bakeApertures(f, o).aperture;
}

// An oblique view over the DEM towards a low sun: terrain in the lower
// part, the sky with the sun's glow above.
FrameSettings view(ShadingMode mode, bool obscurance) {
  FrameSettings s;
  s.mode = mode;
  s.camera.position = {-1800, -1800, 900};
  s.camera.lookAt = {0, 0, 500};
  s.camera.verticalFovDeg = 50;
  setSunAndSky(s.lighting, 45, 12, 2.5);
  s.lighting.exposure = 0.07f;
  s.lighting.hazeDensityPerM = 1e-4f;
  s.obscurance.enabled = obscurance;
  return s;
}

// Largest difference of two RGBA8 pictures, in 8-bit steps.
int largestDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
  return worst;
}

// Reads back an RGBA8 image left in COLOR_ATTACHMENT_OPTIMAL.
std::vector<uint8_t> readAttachment(const Device& device, const Image& image) {
  const size_t bytes = size_t{image.desc().width} * image.desc().height * 4;
  Buffer out(device, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
  submitAndWait(device, [&](VkCommandBuffer cmd) {
    transitionImage(cmd, image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL,
                    VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL);
    copyImageToBuffer(cmd, image, out);
  });
  std::vector<uint8_t> pixels(bytes);
  out.read(pixels.data(), bytes);
  return pixels;
}

class FrameOutputTest : public VulkanTest {};

TEST_F(FrameOutputTest, DisplayValuesEqualTheToneMappedLinearFrame) {
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  for (const auto& [mode, obscurance] :
       {std::pair{ShadingMode::Approx, false}, std::pair{ShadingMode::Approx, true},
        std::pair{ShadingMode::Exact, false}, std::pair{ShadingMode::DebugSkyFill, false},
        std::pair{ShadingMode::DebugTransfer, true}}) {
    const FrameSettings s = view(mode, obscurance);
    const FrameResult direct = renderer.render(scene, s, false);
    const FrameResult linear = renderer.render(scene, s, true);
    // The linear path rounds radiance to half floats before the tone map.
    EXPECT_LE(largestDifference(direct.display, linear.display), 1)
        << "mode " << int(mode) << (obscurance ? " with obscurance" : "");
  }
}

// aal-render --background transparent: pixels without terrain get
// alpha 0, terrain keeps alpha 1, and no colour changes, in every way a frame
// is written (display values from the terrain and sky passes, from the
// composite with obscurances, the tone-map pass after a linear frame, and the
// linear frame itself; the debug views' black background too).
TEST_F(FrameOutputTest, TransparentBackgroundClearsAlphaOnlyWhereThereIsNoTerrain) {
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  for (const auto& [mode, obscurance] :
       {std::pair{ShadingMode::Approx, false}, std::pair{ShadingMode::Approx, true},
        std::pair{ShadingMode::DebugVisible, false}}) {
    FrameSettings s = view(mode, obscurance);
    for (bool linear : {false, true}) {
      const FrameResult opaque = renderer.render(scene, s, linear);
      s.transparentBackground = true;
      const FrameResult clear = renderer.render(scene, s, linear);
      s.transparentBackground = false;
      size_t background = 0, terrain = 0;
      for (size_t i = 0; i < size_t{kWidth} * kHeight; ++i) {
        for (int c = 0; c < 3; ++c) {
          ASSERT_EQ(clear.display[4 * i + c], opaque.display[4 * i + c]) << i;
          if (linear) {
            ASSERT_EQ(clear.linear[4 * i + c], opaque.linear[4 * i + c]) << i;
          }
        }
        ASSERT_EQ(opaque.display[4 * i + 3], 255) << i;
        const uint8_t a = clear.display[4 * i + 3];
        ASSERT_TRUE(a == 0 || a == 255) << i << " " << int(a);
        (a == 0 ? background : terrain) += 1;
        if (linear) {
          ASSERT_EQ(opaque.linear[4 * i + 3], 1.0f) << i;
          ASSERT_EQ(clear.linear[4 * i + 3], a == 0 ? 0.0f : 1.0f) << i;
        }
      }
      // The view has sky above the DEM (top row) and terrain in the lower middle.
      EXPECT_EQ(clear.display[3], 0);
      EXPECT_EQ(clear.display[4 * (size_t{kHeight - 10} * kWidth + kWidth / 2) + 3], 255);
      EXPECT_GT(background, size_t{kWidth} * kHeight / 10) << int(mode) << obscurance << linear;
      EXPECT_GT(terrain, size_t{kWidth} * kHeight / 10) << int(mode) << obscurance << linear;
    }
  }
}

TEST_F(FrameOutputTest, SkyFromItsTableMatchesTheSkyModel) {
  const Heightfield f = fbm();
  const TerrainScene scene(device(), f, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  // Looking up past the DEM: sky in every pixel of the upper half, the sun's
  // glow among them.
  FrameSettings s = view(ShadingMode::Approx, false);
  s.camera.lookAt = {1000, 1000, 1400};
  s.camera.verticalFovDeg = 70;
  const FrameResult frame = renderer.render(scene, s, true);
  const double aspect = double(kWidth) / kHeight;
  const glm::mat4 inverse =
      glm::inverse(projectionMatrix(s.camera, aspect, {10.0, 1e5}) * viewMatrix(s.camera));
  double worst = 0, sum = 0;
  int count = 0;
  for (uint32_t y = 0; y < kHeight / 2; ++y) {
    for (uint32_t x = 0; x < kWidth; ++x) {
      const glm::vec2 ndc((x + 0.5f) / kWidth * 2 - 1, (y + 0.5f) / kHeight * 2 - 1);
      const glm::vec4 far = inverse * glm::vec4(ndc, 1.0f, 1.0f);
      glm::vec3 direction = glm::vec3(far) / far.w - glm::vec3(s.camera.position);
      direction = glm::normalize(direction);
      const glm::vec3 expected = skyRadiance(
          s.lighting.sky, glm::vec3(direction.x, direction.y, std::max(direction.z, 1e-3f)));
      for (int c = 0; c < 3; ++c) {
        const double got = frame.linear[4 * (size_t{y} * kWidth + x) + c];
        const double error = std::abs(got - expected[c]) / std::max(1e-3f, expected[c]);
        worst = std::max(worst, error);
        sum += error;
        ++count;
      }
    }
  }
  std::printf("sky table: relative error mean %.2e, largest %.2e\n", sum / count, worst);
  // Measured: mean 1.2e-3, largest 1.1e-2, at the sun's centre, where the
  // Perez circumsolar term exp(D gamma) has a cusp that linear interpolation
  // across a 1.4 degree texel rounds off.
  EXPECT_LT(sum / count, 2e-3);
  EXPECT_LT(worst, 2e-2);
}

TEST_F(FrameOutputTest, FramesGoStraightIntoAnotherImage) {
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  for (VkFormat format : {VK_FORMAT_R8G8B8A8_UNORM, VK_FORMAT_B8G8R8A8_UNORM}) {
    TerrainRenderer renderer(device(), kWidth, kHeight, format);
    const Image target(device(),
                       {kWidth, kHeight, format,
                        VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                            VK_IMAGE_USAGE_TRANSFER_DST_BIT});
    for (bool obscurance : {false, true}) {
      const FrameSettings s = view(ShadingMode::Approx, obscurance);
      const FrameResult headless = renderer.render(scene, s, false);
      submitAndWait(device(), [&](VkCommandBuffer cmd) {
        renderer.record(cmd, scene, s, {.image = target.handle(), .view = target.view()});
      });
      EXPECT_EQ(readAttachment(device(), target), headless.display)
          << "format " << format << (obscurance ? " with obscurance" : "");
    }
  }
}

// Frames in flight (FrameOutput::frameSlot): the host prepares a frame
// while the one before may still be on the device. Here the second frame is
// recorded after the first, with other settings (the sun, the camera: other
// uniforms, LOD patches and obscurance samples), and runs before it: each
// frame still draws what it was recorded with, its own picture.
TEST_F(FrameOutputTest, FramesInFlightKeepWhatTheyWereRecordedWith) {
  static_assert(kFramesInFlight >= 2, "two frames in flight");
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  FrameSettings first = view(ShadingMode::Approx, true);
  FrameSettings second = first;
  setSunAndSky(second.lighting, 250, 30, 2.5);
  second.camera.position = {1500, -2000, 1400};
  second.obscurance.samples = first.obscurance.samples / 2;
  const FrameResult firstAlone = renderer.render(scene, first, false);
  const FrameResult secondAlone = renderer.render(scene, second, false);
  ASSERT_GT(largestDifference(firstAlone.display, secondAlone.display), 32);

  const ImageDesc desc{kWidth, kHeight, VK_FORMAT_R8G8B8A8_UNORM,
                       VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
  const Image firstTarget(device(), desc), secondTarget(device(), desc);
  submitAndWait(device(), [&](VkCommandBuffer firstCommands) {
    renderer.record(firstCommands, scene, first,
                    {.image = firstTarget.handle(), .view = firstTarget.view(), .frameSlot = 0});
    submitAndWait(device(), [&](VkCommandBuffer secondCommands) {
      renderer.record(
          secondCommands, scene, second,
          {.image = secondTarget.handle(), .view = secondTarget.view(), .frameSlot = 1});
    });
  });
  EXPECT_EQ(largestDifference(readAttachment(device(), firstTarget), firstAlone.display), 0);
  EXPECT_EQ(largestDifference(readAttachment(device(), secondTarget), secondAlone.display), 0);
  // The pass times are the slot's frame's.
  EXPECT_FALSE(renderer.passMilliseconds(1).empty());
  EXPECT_THROW(renderer.passMilliseconds(kFramesInFlight), std::invalid_argument);
  submitAndWait(device(), [&](VkCommandBuffer cmd) {
    EXPECT_THROW(renderer.record(cmd, scene, first, {.frameSlot = kFramesInFlight}),
                 std::invalid_argument);
  });
}

TEST_F(FrameOutputTest, ReducedResolutionIsTheSmallerPictureScaledUp) {
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  TerrainRenderer half(device(), kWidth / 2, kHeight / 2);
  const Image target(device(),
                     {kWidth, kHeight, VK_FORMAT_R8G8B8A8_UNORM,
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT |
                          VK_IMAGE_USAGE_TRANSFER_DST_BIT});
  for (bool obscurance : {false, true}) {
    const FrameSettings s = view(ShadingMode::Approx, obscurance);
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      renderer.record(cmd, scene, s,
                      {.image = target.handle(), .view = target.view(), .resolutionScale = 0.5f});
    });
    const std::vector<uint8_t> scaled = readAttachment(device(), target);
    const FrameResult small = half.render(scene, s, false);
    // Each output pixel lies between four pixels of the half-size picture:
    // it must lie within their range (bilinear scaling, not another picture).
    int outside = 0;
    for (uint32_t y = 0; y < kHeight; ++y) {
      for (uint32_t x = 0; x < kWidth; ++x) {
        const int x0 = std::clamp(int(x / 2) - 1, 0, int(kWidth / 2) - 1);
        const int y0 = std::clamp(int(y / 2) - 1, 0, int(kHeight / 2) - 1);
        for (int c = 0; c < 3; ++c) {
          int lo = 255, hi = 0;
          for (int yy = y0; yy <= std::min(y0 + 2, int(kHeight / 2) - 1); ++yy) {
            for (int xx = x0; xx <= std::min(x0 + 2, int(kWidth / 2) - 1); ++xx) {
              const int v = small.display[4 * (size_t(yy) * (kWidth / 2) + xx) + c];
              lo = std::min(lo, v);
              hi = std::max(hi, v);
            }
          }
          const int v = scaled[4 * (size_t{y} * kWidth + x) + c];
          if (v < lo - 1 || v > hi + 1) ++outside;
        }
      }
    }
    EXPECT_EQ(outside, 0) << (obscurance ? "with obscurance" : "without");
  }
}

// Drawn at half the size (dynamic resolution), the automatic LOD error is
// the full frame's in the pixels drawn (4 at 720 lines), not its share of
// the drawn height (2 at 360), which kept every triangle: fewer triangles,
// the mesh a half-size frame draws when that error is asked of it.
TEST_F(FrameOutputTest, ReducedResolutionKeepsTheFullFramesErrorInThePixelsDrawn) {
  const Heightfield f = fbm(256, 32, 400);
  const TerrainScene scene(device(), f, nullptr, 1000000);
  TerrainRenderer renderer(device(), 1280, 720);
  const Image target(device(),
                     {1280, 720, VK_FORMAT_R8G8B8A8_UNORM,
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT});
  FrameSettings s = view(ShadingMode::BaselineLambert, false);
  s.camera.position = {-4000, -4000, 1500};
  const auto trianglesAt = [&](float scale) {
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      renderer.record(cmd, scene, s,
                      {.image = target.handle(), .view = target.view(), .resolutionScale = scale});
    });
    return renderer.lodSelection().triangles;
  };
  const size_t full = trianglesAt(1.0f), reduced = trianglesAt(0.5f);
  TerrainRenderer half(device(), 640, 360);
  const size_t halfAutomatic = half.render(scene, s, false).triangles;
  FrameSettings asked = s;
  asked.lod.maxErrorPixels = lodAutomaticErrorPixels(720);
  const size_t halfAsked = half.render(scene, asked, false).triangles;
  std::printf(
      "triangles: full %zu, drawn at half %zu, half-size frame %zu (automatic), %zu (4 px)\n", full,
      reduced, halfAutomatic, halfAsked);
  EXPECT_EQ(halfAutomatic, full);  // the same share of the height: the same mesh
  EXPECT_EQ(reduced, halfAsked);
  EXPECT_LT(double(reduced), 0.8 * double(full));
  // An explicit error stays in the pixels drawn.
  s.lod.maxErrorPixels = 2;
  EXPECT_EQ(trianglesAt(0.5f), half.render(scene, s, false).triangles);
}

// Relative RMSE of two RGBA8 pictures of sRGB-encoded values, in linear
// RGB: sqrt(sum |a - b|^2 / sum |b|^2).
double relativeLinearRmse(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  const auto linear = [](uint8_t v) {
    const double c = v / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
  };
  double error = 0, energy = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (i % 4 == 3) continue;
    const double x = linear(a[i]), y = linear(b[i]);
    error += (x - y) * (x - y);
    energy += y * y;
  }
  return std::sqrt(error / energy);
}

// Temporal reconstruction (FrameOutput::temporal, shaders/resolve.glsl):
// along a slow flight drawn at half the size, once the history has filled
// in, the rebuilt frames are within 2 % of the converged picture (8 x 8
// points per pixel: 1.97 %), closer than a frame drawn at full resolution
// (2.37 %), and closer to the full-resolution frames than the smaller
// picture scaled up (3.28 against 4.85 %; the full-resolution frame's single
// point per pixel is itself 2.37 % from the converged picture). With 2 x 2
// points as the converged picture the figures read 2.30 and 2.74 %: that
// picture is itself about 1.2 % from 8 x 8's.
TEST_F(FrameOutputTest, TemporalReconstructionRebuildsTheFullResolutionInMotion) {
  const Heightfield f = fbm(256, 32, 400);
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 1000000);
  constexpr uint32_t kW = 320, kH = 180;
  TerrainRenderer rebuilt(device(), kW, kH), scaled(device(), kW, kH), full(device(), kW, kH);
  constexpr int kConverged = 8;  // points per pixel side of the converged picture
  TerrainRenderer points(device(), kConverged * kW, kConverged * kH);
  const Image target(device(),
                     {kW, kH, VK_FORMAT_R8G8B8A8_UNORM,
                      VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT | VK_IMAGE_USAGE_TRANSFER_SRC_BIT});
  FrameSettings s = view(ShadingMode::Approx, false);
  const auto draw = [&](TerrainRenderer& renderer, bool temporal) {
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      renderer.record(cmd, scene, s,
                      {.image = target.handle(),
                       .view = target.view(),
                       .resolutionScale = 0.5f,
                       .temporal = temporal});
    });
    return readAttachment(device(), target);
  };
  // A flight towards the DEM's centre, 12 m a frame (about a fifth of an
  // output pixel at the centre of the view).
  constexpr int kFrames = 24, kFilled = 8;
  double rebuiltToConverged = 0, fullToConverged = 0, rebuiltToFull = 0, scaledToFull = 0;
  for (int i = 0; i < kFrames; ++i) {
    s.camera.position = glm::dvec3(-4000 + 12.0 * i, -4000 + 12.0 * i, 1500);
    s.camera.lookAt = {0, 0, 300};
    const std::vector<uint8_t> temporal = draw(rebuilt, true);
    const std::vector<uint8_t> upscaled = draw(scaled, false);
    if (i < kFilled) continue;
    const std::vector<uint8_t> one = full.render(scene, s, false).display;
    const std::vector<uint8_t> converged =
        renderSupersampled(points, scene, s, kConverged, false).display;
    rebuiltToConverged += relativeLinearRmse(temporal, converged) / (kFrames - kFilled);
    fullToConverged += relativeLinearRmse(one, converged) / (kFrames - kFilled);
    rebuiltToFull += relativeLinearRmse(temporal, one) / (kFrames - kFilled);
    scaledToFull += relativeLinearRmse(upscaled, one) / (kFrames - kFilled);
  }
  std::printf(
      "mean relative RMSE over frames %d..%d: to 8x8 points rebuilt %.2f %%, full resolution "
      "%.2f %%; to the full-resolution frame rebuilt %.2f %%, scaled up %.2f %%\n",
      kFilled, kFrames - 1, 100 * rebuiltToConverged, 100 * fullToConverged, 100 * rebuiltToFull,
      100 * scaledToFull);
  // The viewer's bar (docs/rendering.md, "Temporal reconstruction").
  EXPECT_LT(rebuiltToConverged, 0.02);
  // Blending display values instead of linear ones read 0.89 of the full
  // resolution's error against 2 x 2 points.
  EXPECT_LT(rebuiltToConverged, 0.86 * fullToConverged);
  EXPECT_LT(rebuiltToFull, 0.75 * scaledToFull);
}

TEST_F(FrameOutputTest, ReducedResolutionNeedsAnOutputImage) {
  const Heightfield f = fbm();
  const TerrainScene scene(device(), f, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  submitAndWait(device(), [&](VkCommandBuffer cmd) {
    EXPECT_THROW(
        renderer.record(cmd, scene, view(ShadingMode::Approx, false), {.resolutionScale = 0.5f}),
        std::invalid_argument);
  });
}

// Supersampled frames (engine/supersampling.h): the mean of each block of
// points, displayed as the renderer displays one point; at one point per
// pixel the renderer's own display values; at 2 x 2 the same picture with
// the terrain's silhouette partly covering its pixels.
FrameResult frameOf(uint32_t width, uint32_t height, const std::vector<float>& linear) {
  FrameResult f;
  f.width = width;
  f.height = height;
  f.linear = linear;
  f.display.assign(size_t{width} * height * 4, 0);
  return f;
}

TEST(FrameOutput, ASupersampledPixelIsTheMeanOfItsBlockDisplayedAsOnePoint) {
  // 4 x 2 points, two pixels of 2 x 2: the first all terrain, the second
  // half sky (alpha 0).
  // clang-format off
  const std::vector<float> linear = {
      1, 2, 3, 1,   3, 2, 1, 1,   10, 0, 0, 1,   0, 0, 0, 0,
      5, 6, 7, 1,   7, 6, 5, 1,   10, 0, 0, 1,   0, 0, 0, 0};
  // clang-format on
  const float exposure = 0.2f;
  const FrameResult out = downsampleFrame(frameOf(4, 2, linear), 2, exposure, false, true);
  ASSERT_EQ(out.width, 2u);
  ASSERT_EQ(out.height, 1u);
  // The second pixel's colour: that of its covered points.
  const glm::vec3 means[2] = {{4, 4, 4}, {10, 0, 0}};
  const float alphas[2] = {1.0f, 0.5f};
  for (int p = 0; p < 2; ++p) {
    const glm::vec3 shown = toneMap(means[p], exposure);
    for (int c = 0; c < 3; ++c) {
      EXPECT_FLOAT_EQ(out.linear[4 * p + c], means[p][c]) << p << c;
      EXPECT_EQ(out.display[4 * p + c], std::lround(255 * shown[c])) << p << c;
    }
    EXPECT_FLOAT_EQ(out.linear[4 * p + 3], alphas[p]);
    EXPECT_EQ(out.display[4 * p + 3], std::lround(255 * alphas[p]));
  }
  // A debug view shows its values clamped to [0, 1], not tone-mapped.
  const FrameResult raw = downsampleFrame(frameOf(4, 2, linear), 2, exposure, true, false);
  EXPECT_TRUE(raw.linear.empty());
  EXPECT_EQ(raw.display[0], 255);
  EXPECT_EQ(raw.display[4], 255);
  EXPECT_EQ(raw.display[5], 0);
}

TEST(FrameOutput, SupersamplingRefusesAFrameItCannotAverage) {
  const std::vector<float> linear(4 * 3 * 2, 0.5f);
  EXPECT_THROW(downsampleFrame(frameOf(3, 2, linear), 2, 1, false, true), std::invalid_argument);
  EXPECT_THROW(downsampleFrame(frameOf(3, 2, linear), 0, 1, false, true), std::invalid_argument);
  EXPECT_THROW(downsampleFrame(frameOf(3, 2, {}), 1, 1, false, true), std::invalid_argument);
}

TEST_F(FrameOutputTest, SupersamplingOnePointPerPixelIsTheRenderersOwnDisplay) {
  // The CPU's tone map of the linear frame against the device's (the same
  // formulas: tone_map.h and shaders/tone_map.glsl), in the tone-mapped
  // modes and a debug view, with and without a background.
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer renderer(device(), kWidth, kHeight);
  for (const auto& [mode, obscurance, transparent] :
       {std::tuple{ShadingMode::Approx, false, false}, std::tuple{ShadingMode::Approx, true, true},
        std::tuple{ShadingMode::Exact, false, false},
        std::tuple{ShadingMode::DebugSkyFill, false, false}}) {
    FrameSettings s = view(mode, obscurance);
    s.transparentBackground = transparent;
    const FrameResult frame = renderer.render(scene, s, true);
    const FrameResult same =
        downsampleFrame(frame, 1, s.lighting.exposure, isDebugMode(mode), true);
    EXPECT_LE(largestDifference(frame.display, same.display), 1) << int(mode);
    EXPECT_EQ(frame.linear, same.linear) << int(mode);
  }
}

TEST_F(FrameOutputTest, SupersamplingTwoByTwoIsTheSamePictureWithCoverageAtTheSilhouette) {
  const Heightfield f = fbm();
  const ApertureMap aperture = bake(f);
  const TerrainScene scene(device(), f, aperture, nullptr, 100000);
  TerrainRenderer one(device(), kWidth, kHeight), four(device(), 2 * kWidth, 2 * kHeight);
  FrameSettings s = view(ShadingMode::Approx, true);
  s.transparentBackground = true;
  const FrameResult plain = one.render(scene, s, true);
  const FrameResult smooth =
      downsampleFrame(four.render(scene, s, true), 2, s.lighting.exposure, false, true);
  ASSERT_EQ(smooth.width, kWidth);
  ASSERT_EQ(smooth.height, kHeight);
  double sum = 0;
  size_t partial = 0, partialBefore = 0;
  for (size_t i = 0; i < size_t{kWidth} * kHeight; ++i) {
    for (int c = 0; c < 3; ++c)
      sum += std::abs(int(smooth.display[4 * i + c]) - int(plain.display[4 * i + c]));
    const uint8_t a = smooth.display[4 * i + 3], before = plain.display[4 * i + 3];
    partial += a > 0 && a < 255;
    partialBefore += before > 0 && before < 255;
  }
  const double mean = sum / (3.0 * kWidth * kHeight);
  std::printf("2 x 2 against one point: mean |difference| %.2f of 255; %zu pixels partly terrain\n",
              mean, partial);
  // The same picture: what differs is where a pixel holds detail or an edge.
  EXPECT_LT(mean, 3.0);
  // The silhouette against the sky: partly covered pixels, which one point
  // per pixel cannot have (about one per column of the image).
  EXPECT_EQ(partialBefore, 0u);
  EXPECT_GT(partial, size_t{kWidth} / 2);
}

}  // namespace
}  // namespace aal
