// The obscurance/W passes of the renderer (docs/design.md §6) under validation:
// O and W on simple terrains, the albedo limits, the composite, and the noise
// reduction of interleaved sampling against a high-sample CPU estimate.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include <glm/geometric.hpp>
#include <glm/matrix.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/terrain/light/obscurance_samples.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr int kSize = 96;          // DEM texels and image pixels per side
constexpr double kCellM = 10.0;    // DEM cell size
constexpr float kRadiusM = 80.0f;  // obscurance radius in the tests

template <typename F>
Heightfield makeField(F f) {
  Heightfield h;
  h.width = h.height = kSize;
  h.cellSizeXM = h.cellSizeYM = kCellM;
  h.z.resize(h.texelCount());
  for (int row = 0; row < kSize; ++row) {
    for (int col = 0; col < kSize; ++col) {
      const double x = (col - (kSize - 1) / 2.0) * kCellM, y = ((kSize - 1) / 2.0 - row) * kCellM;
      h.z[h.index(col, row)] = static_cast<float>(f(x, y));
    }
  }
  return h;
}

// A north-south trench 60 m deep with a floor 20 m wide and 60-degree walls.
Heightfield trench() {
  return makeField([](double x, double) {
    const double d = std::abs(x);
    return 200.0 - (d < 10 ? 60.0 : d < 45 ? 60.0 - (d - 10) * 60.0 / 35.0 : 0.0);
  });
}

// Smooth hills and valleys, features much wider than the 4x4 filter.
Heightfield waves() {
  return makeField([](double x, double y) {
    return 300 + 140 * std::sin(x / 140) * std::cos(y / 180) + 60 * std::sin((x + y) / 90);
  });
}

// Straight down from high above with a narrow field of view, so the image is
// almost an orthographic map of the DEM: pixel (i, j) sees about texel (i, j).
FrameSettings topView(ShadingMode mode) {
  FrameSettings s;
  s.mode = mode;
  s.camera.position = {0, 0, 50000};
  s.camera.lookAt = {0, 0, 0};
  s.camera.verticalFovDeg =
      2 * std::atan(0.5 * (kSize - 1) * kCellM / 50000) * 180 / std::numbers::pi;
  setSunAndSky(s.lighting, 200, 35, 2.5);
  s.lighting.exposure = 0.07f;
  s.obscurance.radiusM = kRadiusM;
  return s;
}

struct Scene {
  Heightfield field;
  ApertureMap aperture;
  std::unique_ptr<TerrainScene> gpu;
  Scene(const Device& device, Heightfield f) : field(std::move(f)) {
    BakeOptions o;
    o.azimuths = 16;
    aperture = bakeApertures(field, o).aperture;
    gpu = std::make_unique<TerrainScene>(device, field, aperture, nullptr, 100000);
  }
};

float channel(const FrameResult& frame, int x, int y, int c) {
  return frame.linear[4 * (static_cast<size_t>(y) * frame.width + x) + c];
}

// The texel that pixel (x, y) sees: the pixel's ray through the inverse of
// the renderer's matrices, intersected with the bilinear surface by
// fixed-point iteration (the ray is within 0.6 degrees of vertical).
glm::vec2 texelSeenBy(const Heightfield& h, const Camera& camera, int x, int y) {
  const DepthRange range = depthRangeFor(camera, h);
  const glm::dmat4 inverse =
      glm::inverse(glm::dmat4(projectionMatrix(camera, 1.0, range) * viewMatrix(camera)));
  const glm::dvec2 ndc(2 * (x + 0.5) / kSize - 1, 2 * (y + 0.5) / kSize - 1);
  const glm::dvec4 nearPoint = inverse * glm::dvec4(ndc, 0, 1),
                   farPoint = inverse * glm::dvec4(ndc, 1, 1);
  const glm::dvec3 a = glm::dvec3(nearPoint) / nearPoint.w, b = glm::dvec3(farPoint) / farPoint.w;
  const glm::dvec3 dir = glm::normalize(b - a);
  glm::vec2 texel(0);
  double z = 0;
  for (int i = 0; i < 20; ++i) {
    const glm::dvec3 p = a + dir * ((a.z - z) / -dir.z);
    texel = {static_cast<float>(p.x / kCellM + (kSize - 1) / 2.0),
             static_cast<float>((kSize - 1) / 2.0 - p.y / kCellM)};
    z = bilinearHeight(h, texel);
  }
  return texel;
}

class ObscuranceRender : public VulkanTest {};

TEST_F(ObscuranceRender, FlatGroundHasNoObscurance) {
  Scene scene(device(), makeField([](double, double) { return 120.0; }));
  TerrainRenderer renderer(device(), 64, 48);
  for (ShadingMode mode : {ShadingMode::DebugObscurance, ShadingMode::DebugTransfer}) {
    FrameSettings s = topView(mode);
    s.camera.position = {300, -900, 500};  // oblique: terrain and sky
    s.camera.verticalFovDeg = 60;
    const FrameResult frame = renderer.render(*scene.gpu, s, true);
    int terrain = 0;
    for (int y = 0; y < 48; ++y) {
      for (int x = 0; x < 64; ++x) {
        if (channel(frame, x, y, 0) == 0) continue;  // sky is black in debug views
        ++terrain;
        for (int c = 0; c < 3; ++c) ASSERT_EQ(channel(frame, x, y, c), 1.0f) << x << "," << y;
      }
    }
    EXPECT_GT(terrain, 64 * 48 / 5);
  }
}

TEST_F(ObscuranceRender, TrenchIsDarkInsideAndOpenFarAway) {
  Scene scene(device(), trench());
  TerrainRenderer renderer(device(), kSize, kSize);
  // At full resolution: the half-resolution filter spans 80 m, four times
  // the trench's floor.
  FrameSettings s = topView(ShadingMode::DebugObscurance);
  s.obscurance.halfResolution = false;
  const FrameResult frame = renderer.render(*scene.gpu, s, true);
  const int mid = kSize / 2;
  // μ(d) = sqrt(d/R) weighs near occluders little: O = 0.86 here.
  EXPECT_LT(channel(frame, mid, mid, 0), 0.9f) << "trench floor";
  EXPECT_EQ(channel(frame, 5, mid, 0), 1.0f) << "plain far to the west";
  EXPECT_EQ(channel(frame, kSize - 5, mid, 0), 1.0f) << "plain far to the east";
  EXPECT_EQ(channel(frame, mid, mid, 0), channel(frame, mid, mid, 1)) << "O is grey";
}

TEST_F(ObscuranceRender, TransferFollowsTheAlbedoBetweenObscuranceAndOne) {
  Scene scene(device(), trench());
  TerrainRenderer renderer(device(), kSize, kSize);
  const FrameResult o = renderer.render(*scene.gpu, topView(ShadingMode::DebugObscurance), true);
  auto transfer = [&](float albedo) {
    FrameSettings s = topView(ShadingMode::DebugTransfer);
    s.albedoValue = glm::vec3(albedo);
    return renderer.render(*scene.gpu, s, true);
  };
  const FrameResult black = transfer(0.0f), grey = transfer(0.5f), snow = transfer(1.0f);
  int darkened = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const float obscurance = channel(o, x, y, 0);
      darkened += obscurance < 0.97f;
      ASSERT_EQ(channel(black, x, y, 1), obscurance) << "a = 0: W = O at " << x << "," << y;
      ASSERT_GE(channel(grey, x, y, 1), obscurance) << x << "," << y;
      ASSERT_LE(channel(grey, x, y, 1), 1.0f) << x << "," << y;
      ASSERT_EQ(channel(snow, x, y, 1), 1.0f) << "a = 1: W = 1 at " << x << "," << y;
    }
  }
  EXPECT_GT(darkened, kSize * 4) << "the trench must darken a band of the image";
}

TEST_F(ObscuranceRender, WMultipliesOnlyTheSkyFill) {
  Scene scene(device(), trench());
  TerrainRenderer renderer(device(), kSize, kSize);
  FrameSettings s = topView(ShadingMode::Approx);
  FrameSettings off = s;
  off.obscurance.enabled = false;
  const FrameResult withW = renderer.render(*scene.gpu, s, true);
  const FrameResult withoutW = renderer.render(*scene.gpu, off, true);
  const int mid = kSize / 2;
  // The composite keeps everything but the sky fill: W <= 1 only darkens, in
  // the trench, and leaves the open plain as it was.
  EXPECT_LT(channel(withW, mid, mid, 2), 0.98f * channel(withoutW, mid, mid, 2));
  for (size_t i = 0; i < withW.linear.size(); ++i) {
    // Half-float targets: a few roundings apart.
    ASSERT_LE(withW.linear[i], withoutW.linear[i] * (1 + 2e-3f)) << i;
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(channel(withW, 5, mid, c), channel(withoutW, 5, mid, c),
                1e-3f * channel(withoutW, 5, mid, c));
  }
  // No sky light: nothing for W to multiply, the same picture.
  s.lighting.skyRadiance = off.lighting.skyRadiance = glm::vec3(0.0f);
  const FrameResult dark = renderer.render(*scene.gpu, s, true);
  const FrameResult darkOff = renderer.render(*scene.gpu, off, true);
  EXPECT_EQ(dark.linear, darkOff.linear);
}

// Mean squared difference over the image to a per-pixel reference.
double meanSquaredError(const FrameResult& frame, const std::vector<float>& reference) {
  double sum = 0;
  for (int i = 0; i < kSize * kSize; ++i) {
    const double d = frame.linear[4 * static_cast<size_t>(i)] - reference[static_cast<size_t>(i)];
    sum += d * d;
  }
  return sum / (kSize * kSize);
}

TEST_F(ObscuranceRender, InterleavingAndFilteringCutTheErrorVariance) {
  Scene scene(device(), waves());
  TerrainRenderer renderer(device(), kSize, kSize);
  // R spans 20 pixels, as the default R does in a 1280x720 view of jacksboro.
  const float radiusM = 200;
  FrameSettings s = topView(ShadingMode::DebugObscurance);
  s.obscurance.radiusM = radiusM;
  const ObscuranceField field{[&](glm::vec2 t) { return bilinearHeight(scene.field, t); },
                              [](glm::vec2) { return glm::vec3(0.0f); },
                              glm::vec2(static_cast<float>(kCellM))};
  // High-sample CPU estimate of the same estimator (m = 1): 4096 random rays.
  std::mt19937 rng(31);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<glm::vec3> many(4096);
  for (glm::vec3& v : many) v = obscuranceOffset({u(rng), u(rng), u(rng)});
  std::vector<glm::vec2> texels(kSize * kSize);
  std::vector<float> reference(kSize * kSize), oneSetCpu(kSize * kSize);
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const size_t i = static_cast<size_t>(y) * kSize + x;
      texels[i] = texelSeenBy(scene.field, s.camera, x, y);
      reference[i] = estimateObscurance(field, many, texels[i], radiusM, 1, 0).obscurance;
    }
  }
  for (int n : {8, 16, 32}) {
    FrameSettings oneSet = s;
    oneSet.obscurance.samples = n;
    oneSet.obscurance.interleaved = false;
    oneSet.obscurance.halfResolution = false;
    FrameSettings full = oneSet, half = oneSet;
    full.obscurance.interleaved = half.obscurance.interleaved = true;
    half.obscurance.halfResolution = true;
    const FrameResult a = renderer.render(*scene.gpu, full, true);
    const FrameResult b = renderer.render(*scene.gpu, oneSet, true);
    const FrameResult c = renderer.render(*scene.gpu, half, true);
    // The one-set image is the CPU estimator with the same set, up to the
    // sampler's precision and the pixel's exact surface point.
    double cpuDifference = 0;
    for (size_t i = 0; i < texels.size(); ++i) {
      const float cpu =
          estimateObscurance(field, obscuranceSampleOffsets(n), texels[i], radiusM, 1, 0)
              .obscurance;
      cpuDifference += std::abs(b.linear[4 * i] - cpu) / static_cast<double>(texels.size());
    }
    const double errorFull = meanSquaredError(a, reference);
    const double errorOneSet = meanSquaredError(b, reference);
    const double errorHalf = meanSquaredError(c, reference);
    std::printf(
        "n=%d: error variance vs 4096-sample CPU estimate: one set %.3g, interleaved + filtered "
        "%.3g (%.1fx less), at half resolution %.3g (%.1fx less); one set vs CPU estimator: mean "
        "|difference| %.2g\n",
        n, errorOneSet, errorFull, errorOneSet / errorFull, errorHalf, errorOneSet / errorHalf,
        cpuDifference);
    // Interleaving and the filter: at least 4x less error variance for every
    // n. The 16 sets differ in elevation and distance too (Cranley-Patterson
    // shifts, obscurance_samples.h), so the filtered error keeps falling with
    // n (docs/obscurance.md).
    EXPECT_GT(errorOneSet, 4.0 * errorFull) << n;
    EXPECT_GT(errorOneSet, 4.0 * errorHalf) << n;
    EXPECT_LT(cpuDifference, 0.01) << n;
  }
}

}  // namespace
}  // namespace aal
