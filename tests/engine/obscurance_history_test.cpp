// Temporal reuse of obscurance samples (ObscuranceSettings::History, the
// viewer while the view moves; shaders/obscurance_pass.glsl): at rest it is
// the frame without reuse; reused samples lower the noise of a moving view;
// samples never travel to another surface (no ghosting).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr int kSize = 128;         // DEM texels per side
constexpr double kCellM = 10.0;    // cell size
constexpr uint32_t kPixels = 128;  // image width and height

// West half: a field of north-south trenches (low W); east half: flat
// ground (W = 1: nothing within the radius rises above it).
Heightfield trenchesAndPlain() {
  Heightfield h;
  h.width = h.height = kSize;
  h.cellSizeXM = h.cellSizeYM = kCellM;
  h.z.resize(h.texelCount());
  for (int row = 0; row < kSize; ++row) {
    for (int col = 0; col < kSize; ++col) {
      const bool trenches = col < kSize / 2 - 10;
      h.z[h.index(col, row)] =
          trenches ? static_cast<float>(100 + 40 * std::abs(std::sin(col * 0.35))) : 100.0f;
    }
  }
  return h;
}

FrameSettings view(glm::dvec3 position, glm::dvec3 lookAt, ObscuranceSettings::History history) {
  FrameSettings s;
  s.mode = ShadingMode::DebugTransfer;  // W itself
  s.camera.position = position;
  s.camera.lookAt = lookAt;
  s.camera.verticalFovDeg = 40;
  setSunAndSky(s.lighting, 200, 35, 2.5);
  s.obscurance.radiusM = 60;
  s.obscurance.history = history;
  return s;
}

// Mean absolute difference of the W pictures over pixels both show terrain
// (debug views leave the sky black).
double meanDifference(const FrameResult& a, const FrameResult& b) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < a.display.size(); i += 4) {
    const bool terrain = a.display[i + 1] > 0 && b.display[i + 1] > 0;
    if (!terrain) continue;
    for (int c = 0; c < 3; ++c) sum += std::abs(int(a.display[i + c]) - int(b.display[i + c]));
    n += 3;
  }
  return n ? sum / double(n) / 255.0 : 1.0;
}

class ObscuranceHistory : public VulkanTest {
 protected:
  void SetUp() override {
    VulkanTest::SetUp();
    field_ = trenchesAndPlain();
    BakeOptions o;
    o.azimuths = 8;
    aperture_ = bakeApertures(field_, o).aperture;
  }
  Heightfield field_;
  ApertureMap aperture_;
};

using History = ObscuranceSettings::History;
const glm::dvec3 kOverTrenches(-700, -900, 700), kTrenchTarget(-300, 0, 100);

TEST_F(ObscuranceHistory, AtRestItIsTheFrameWithoutReuse) {
  const TerrainScene scene(device(), field_, aperture_, nullptr, 100000);
  TerrainRenderer renderer(device(), kPixels, kPixels);
  const FrameResult plain =
      renderer.render(scene, view(kOverTrenches, kTrenchTarget, History::None), false);
  const FrameResult refresh =
      renderer.render(scene, view(kOverTrenches, kTrenchTarget, History::Refresh), false);
  // A still camera reusing a complete history keeps it as it is.
  const FrameResult reuse =
      renderer.render(scene, view(kOverTrenches, kTrenchTarget, History::Reuse), false);
  int worst = 0, worstReuse = 0;
  for (size_t i = 0; i < plain.display.size(); ++i) {
    worst = std::max(worst, std::abs(int(plain.display[i]) - int(refresh.display[i])));
    worstReuse = std::max(worstReuse, std::abs(int(plain.display[i]) - int(reuse.display[i])));
  }
  // The means per sample are kept as half floats.
  EXPECT_LE(worst, 1);
  EXPECT_LE(worstReuse, 1);
}

TEST_F(ObscuranceHistory, ReusedSamplesLowerTheNoiseOfAMovingView) {
  const TerrainScene scene(device(), field_, aperture_, nullptr, 100000);
  const glm::dvec3 step(4, 3, 0);  // the camera moves 5 m between frames
  const FrameResult full =
      TerrainRenderer(device(), kPixels, kPixels)
          .render(scene, view(kOverTrenches + step, kTrenchTarget + step, History::None), false);
  // With a history of the previous position...
  TerrainRenderer reusing(device(), kPixels, kPixels);
  reusing.render(scene, view(kOverTrenches, kTrenchTarget, History::Refresh), false);
  const FrameResult withHistory = reusing.render(
      scene, view(kOverTrenches + step, kTrenchTarget + step, History::Reuse), false);
  // ... and with one of a view that shares no surface point with it (looking
  // the other way): only this frame's quarter of the samples.
  TerrainRenderer fresh(device(), kPixels, kPixels);
  fresh.render(scene, view({600, 900, 700}, {600, 2000, 100}, History::Refresh), false);
  const FrameResult withoutHistory =
      fresh.render(scene, view(kOverTrenches + step, kTrenchTarget + step, History::Reuse), false);
  const double reused = meanDifference(withHistory, full);
  const double alone = meanDifference(withoutHistory, full);
  std::printf(
      "mean |W - full estimate|: %.4f with the history, %.4f with a quarter of the "
      "samples\n",
      reused, alone);
  EXPECT_GT(alone, 0.005);  // a quarter of the samples is noticeably noisier
  // The reference is an estimate with its own noise sigma (n samples): a
  // perfect reuse (n samples again) differs from it by sqrt(2) sigma, a
  // quarter of the samples (2 sigma) by sqrt(5) sigma: a ratio of 0.63.
  // Measured 0.52 (the 4x4 filter evens out part of the noise); without
  // reuse it is 1.
  EXPECT_LT(reused, 0.7 * alone);
}

TEST_F(ObscuranceHistory, SamplesNeverMoveToAnotherSurface) {
  const TerrainScene scene(device(), field_, aperture_, nullptr, 100000);
  TerrainRenderer renderer(device(), kPixels, kPixels);
  // The trenches fill the first view; the second turns to the plain, whose W
  // is 1 everywhere. History kept at the same pixels (not reprojected by
  // surface point) would pull the plain's W down towards the trenches'.
  renderer.render(scene, view(kOverTrenches, kTrenchTarget, History::Refresh), false);
  const FrameResult plain =
      renderer.render(scene, view({600, -200, 500}, {600, 0, 100}, History::Reuse), false);
  int low = 0, terrain = 0;
  for (size_t i = 0; i < plain.display.size(); i += 4) {
    if (plain.display[i + 1] == 0) continue;  // sky
    ++terrain;
    if (plain.display[i + 1] < 250) ++low;
  }
  EXPECT_GT(terrain, int(kPixels * kPixels / 3));
  EXPECT_EQ(low, 0) << "pixels of the plain with W below 250/255";
}

}  // namespace
}  // namespace aal
