// Supersampled frames (engine/supersampling.h): the mean of each block of
// points, displayed as the renderer displays one point; at one point per
// pixel the renderer's own display values; at 2 x 2 the same picture with
// the terrain's silhouette partly covering its pixels.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "aperture/engine/supersampling.h"
#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr uint32_t kWidth = 160, kHeight = 96;

Heightfield fbm() {
  SyntheticTerrainOptions o;
  o.width = o.height = 96;
  o.cellSizeM = 30;
  o.featureSizeTexels = 24;
  o.amplitudeM = 300;
  return makeSyntheticTerrain(o);
}

ApertureMap bake(const Heightfield& f) {
  BakeOptions o;
  o.azimuths = 16;
  return bakeApertures(f, o).aperture;
}

// Terrain in the lower part, sky with the sun's glow above.
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

int largestDifference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  int worst = 0;
  for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, std::abs(int(a[i]) - int(b[i])));
  return worst;
}

FrameResult frameOf(uint32_t width, uint32_t height, const std::vector<float>& linear) {
  FrameResult f;
  f.width = width;
  f.height = height;
  f.linear = linear;
  f.display.assign(size_t{width} * height * 4, 0);
  return f;
}

TEST(Supersampling, EachPixelIsTheMeanOfItsBlockDisplayedAsOnePoint) {
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

TEST(Supersampling, RefusesAFrameItCannotAverage) {
  const std::vector<float> linear(4 * 3 * 2, 0.5f);
  EXPECT_THROW(downsampleFrame(frameOf(3, 2, linear), 2, 1, false, true), std::invalid_argument);
  EXPECT_THROW(downsampleFrame(frameOf(3, 2, linear), 0, 1, false, true), std::invalid_argument);
  EXPECT_THROW(downsampleFrame(frameOf(3, 2, {}), 1, 1, false, true), std::invalid_argument);
}

class SupersamplingTest : public VulkanTest {};

TEST_F(SupersamplingTest, OnePointPerPixelIsTheRenderersOwnDisplay) {
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

TEST_F(SupersamplingTest, TwoByTwoIsTheSamePictureWithCoverageAtTheSilhouette) {
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
