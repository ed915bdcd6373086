// Frame time of the headless renderer at 1280x720 per shading mode, on the
// DEM given by AAL_BENCH_DEM (default: the shipped jacksboro DEM). Target
// (issue 5): approx within 15% of baseline-lambert.
#include <benchmark/benchmark.h>

#include <cstdlib>
#include <memory>

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
    scene = std::make_unique<aal::TerrainScene>(device, field, aperture, nullptr, 2'000'000);
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

}  // namespace

BENCHMARK_MAIN();
