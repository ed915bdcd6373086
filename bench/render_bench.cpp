// Frame time of the headless renderer at 1280x720 per shading mode, on the
// DEM given by AAL_BENCH_DEM (default: the shipped jacksboro DEM), coloured
// by the image AAL_BENCH_ALBEDO (default: the palette). Target
// (issue 5): approx within 15% of baseline-lambert.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>
#include <optional>

#include "albedo_image.h"
#include "bake.h"
#include "camera.h"
#include "dem_loader.h"
#include "device.h"
#include "instance.h"
#include "sky_lighting.h"
#include "terrain_renderer.h"
#include "terrain_scene.h"

#ifndef AAL_SOURCE_DIR
#define AAL_SOURCE_DIR "."
#endif

namespace {

struct Fixture {
  aal::Instance instance;
  aal::Device device{instance};
  aal::Heightfield field;
  std::unique_ptr<aal::TerrainScene> scene;
  std::unique_ptr<aal::TerrainRenderer> renderer;
  aal::FrameSettings settings;

  Fixture() {
    const char* dem = std::getenv("AAL_BENCH_DEM");
    field = aal::loadDem(dem ? dem : AAL_SOURCE_DIR "/heightmaps/jacksboro_fault_dem.tif");
    const aal::ApertureMap aperture = aal::bakeApertures(field, {}).aperture;
    // AAL_BENCH_ALBEDO: an albedo image (resampled to the DEM); default: the palette.
    const char* albedoPath = std::getenv("AAL_BENCH_ALBEDO");
    std::optional<aal::AlbedoImage> albedo;
    if (albedoPath) albedo = aal::loadAlbedoImage(albedoPath, field.width, field.height, nullptr);
    scene = std::make_unique<aal::TerrainScene>(device, field, aperture,
                                                albedo ? &*albedo : nullptr, 2'000'000);
    renderer = std::make_unique<aal::TerrainRenderer>(device, 1280, 720);
    const aal::SkyLighting light = aal::makeSkyLighting(250, 25, 2.5);
    settings.camera = aal::defaultCamera(field, 1280.0 / 720.0);
    settings.sunDirection = light.sunDirection;
    settings.sunIrradiance = light.sunIrradiance;
    settings.skyRadiance = light.skyRadiance;
    settings.sky = light.sky;
    settings.exposure = 0.07f;
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_RenderFrame(benchmark::State& state) {
  Fixture& f = fixture();
  f.settings.mode = static_cast<aal::ShadingMode>(state.range(0));
  f.settings.obscurance.enabled = false;  // the frame of issue 5; see BM_RenderObscurance
  double gpuMs = 0;
  for (auto _ : state) {
    const aal::FrameResult frame = f.renderer->render(*f.scene, f.settings, false);
    for (const auto& pass : frame.passMilliseconds) gpuMs += pass.second;
  }
  state.counters["gpu_ms"] = gpuMs / static_cast<double>(state.iterations());
  state.SetLabel(state.range(0) == 0   ? "approx"
                 : state.range(0) == 1 ? "exact"
                 : state.range(0) == 2 ? "baseline-lambert"
                                       : "baseline-ao");
}
BENCHMARK(BM_RenderFrame)->DenseRange(0, 3)->Unit(benchmark::kMillisecond)->UseRealTime();

// The approx frame with the obscurance passes (issue 6) for n = 0 (off), 8,
// 16, 32 at half (second argument 1) or full resolution (0). Target: the
// default n within 1.5x of the frame without the passes. Counters: GPU time
// of the whole frame and of the obscurance, filter and composite passes.
void BM_RenderObscurance(benchmark::State& state) {
  Fixture& f = fixture();
  f.settings.mode = aal::ShadingMode::Approx;
  f.settings.obscurance.enabled = state.range(0) > 0;
  f.settings.obscurance.samples = state.range(0) > 0 ? static_cast<int>(state.range(0)) : 16;
  f.settings.obscurance.halfResolution = state.range(1) != 0;
  double gpuMs = 0, obscuranceMs = 0;
  for (auto _ : state) {
    const aal::FrameResult frame = f.renderer->render(*f.scene, f.settings, false);
    for (const auto& [pass, ms] : frame.passMilliseconds) {
      gpuMs += ms;
      if (pass == "obscurance" || pass == "obscurance filter" || pass == "composite") {
        obscuranceMs += ms;
      }
    }
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["gpu_ms"] = gpuMs / n;
  state.counters["obscurance_ms"] = obscuranceMs / n;
}
BENCHMARK(BM_RenderObscurance)
    ->ArgsProduct({{0, 8, 16, 32}, {1}})
    ->Args({16, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
