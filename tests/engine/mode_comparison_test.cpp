// The GPU's shading modes against the CPU reference (tools/mode_comparison):
// the whole pipeline agrees where nothing is approximated, and ambient
// aperture lighting beats the no-aperture baselines where shadows matter.
#include "aperture/tools/mode_comparison.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "aperture/engine/terrain_scene.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

Heightfield flatGround() {
  Heightfield f;
  f.width = f.height = 65;
  f.cellSizeXM = f.cellSizeYM = 30;
  f.format = "test";
  f.z.assign(f.texelCount(), 250.0f);
  return f;
}

Heightfield mountains() {
  SyntheticTerrainOptions s;
  s.width = s.height = 96;
  s.cellSizeM = 30;
  s.amplitudeM = 900;
  s.featureSizeTexels = 24;
  s.seed = 5;
  return makeSyntheticTerrain(s);
}

FrameSettings obliqueView(const Heightfield& f, double sunAzimuthDeg, double sunElevationDeg) {
  FrameSettings s;
  const double half = 0.5 * (f.width - 1) * f.cellSizeXM;
  s.camera.position = {1.2 * half, -1.6 * half, 2.2 * half};
  s.camera.lookAt = {0, 0, 200};
  s.camera.verticalFovDeg = 45;
  setSunAndSky(s.lighting, sunAzimuthDeg, sunElevationDeg, 2.5);
  s.lighting.exposure = 0.07f;
  s.obscurance.enabled = false;  // the reference has no near-field term to match W against
  return s;
}

std::map<std::string, double> errors(const Device& device, const Heightfield& f,
                                     const FrameSettings& settings) {
  BakeOptions bake;
  bake.azimuths = 64;
  const ApertureMap aperture = bakeApertures(f, bake).aperture;
  const TerrainScene scene(device, f, aperture, nullptr, 200000);
  TerrainRenderer renderer(device, 96, 64);
  ComparisonOptions options;
  options.sunRays = 16;
  options.skyRays = 256;
  const Comparison c =
      compareModes(renderer, scene, f, settings, defaultComparedModes(settings), options);
  std::map<std::string, double> byMode;
  for (const ModeError& e : c.modes) {
    byMode[e.mode] = e.relativeRmse;
    std::printf("%-18s relative RMSE %.2f %%\n", e.mode.c_str(), 100 * e.relativeRmse);
  }
  size_t terrain = 0;
  for (uint8_t m : c.mask) terrain += m;
  EXPECT_GT(terrain, c.mask.size() / 4) << "the view must be mostly terrain";
  return byMode;
}

class ModeComparison : public VulkanTest {};

TEST_F(ModeComparison, OpenFlatGroundAgreesInEveryMode) {
  // Nothing to approximate: every mode is N.L sun plus the whole sky, and the
  // reference must find the same (camera, radiometry and haze included).
  const Heightfield f = flatGround();
  FrameSettings s = obliqueView(f, 135, 35);
  s.lighting.hazeDensityPerM = 2e-5f;
  for (const auto& [mode, error] : errors(device(), f, s)) EXPECT_LT(error, 0.01) << mode;
}

TEST_F(ModeComparison, ApertureLightingBeatsTheBaselinesUnderALowSun) {
  // Long shadows: the baselines light what the terrain hides from the sun.
  const Heightfield f = mountains();
  const std::map<std::string, double> e = errors(device(), f, obliqueView(f, 250, 12));
  EXPECT_LT(e.at("approx"), e.at("baseline-lambert"));
  EXPECT_LT(e.at("exact"), e.at("baseline-lambert"));
  EXPECT_LT(e.at("approx"), e.at("baseline-ao"));
}

}  // namespace
}  // namespace aal
