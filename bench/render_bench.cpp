// Frame time of the headless renderer at 1280x720 per shading mode, on the
// DEM given by AAL_BENCH_DEM (default: the shipped jacksboro DEM), coloured
// by the image AAL_BENCH_ALBEDO (default: the palette). Target
// (docs/performance.md, "Rendering"): approx within 15% of baseline-lambert.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <map>
#include <memory>
#include <optional>
#include <utility>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/preprocess/bake.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/io/albedo_image.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/terrain/view/camera.h"

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
    aal::BakeOptions bake;
    bake.horizons = true;  // for the horizon mode (BM_RenderFrame/10)
    // AAL_BENCH_HORIZON_DIRECTIONS, AAL_BENCH_HORIZON_BITS: the horizons' layout
    // (default 8 directions of 8 bits; docs/performance.md measures 16 of 4).
    if (const char* d = std::getenv("AAL_BENCH_HORIZON_DIRECTIONS")) {
      bake.horizonDirections = std::atoi(d);
    }
    if (const char* b = std::getenv("AAL_BENCH_HORIZON_BITS")) bake.horizonBits = std::atoi(b);
    const aal::BakeResult baked = aal::bakeApertures(field, bake);
    const aal::ApertureMap& aperture = baked.aperture;
    // AAL_BENCH_ALBEDO: an albedo image (resampled to the DEM); default: the palette.
    const char* albedoPath = std::getenv("AAL_BENCH_ALBEDO");
    std::optional<aal::AlbedoImage> albedo;
    if (albedoPath) albedo = aal::loadAlbedoImage(albedoPath, field.width, field.height, nullptr);
    scene = std::make_unique<aal::TerrainScene>(device, field, aperture,
                                                albedo ? &*albedo : nullptr, 2'000'000);
    scene->setHorizons(device, baked.horizons);
    renderer = std::make_unique<aal::TerrainRenderer>(device, 1280, 720);
    settings.camera = aal::defaultCamera(field, 1280.0 / 720.0);
    // AAL_BENCH_SUN_AZIMUTH (degrees, default 250): at 250 the two stored
    // horizon directions beside the sun lie in one layer of rotation 0 for 8
    // and 16 directions; at 285 in two (the renderer before the rotated
    // layout fetched two layers there; now it re-lays them for rotation 2 in
    // the first frame, docs/rendering.md; docs/performance.md).
    // AAL_BENCH_SUN_ELEVATION (degrees, default 25): a low sun, where the
    // horizon mode differs from approx.
    const char* sunAzimuth = std::getenv("AAL_BENCH_SUN_AZIMUTH");
    const char* sunElevation = std::getenv("AAL_BENCH_SUN_ELEVATION");
    aal::setSunAndSky(settings.lighting, sunAzimuth ? std::atof(sunAzimuth) : 250.0,
                      sunElevation ? std::atof(sunElevation) : 25.0, 2.5);
    settings.lighting.exposure = 0.07f;
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_RenderFrame(benchmark::State& state) {
  Fixture& f = fixture();
  f.settings.mode = static_cast<aal::ShadingMode>(state.range(0));
  f.settings.obscurance.enabled = false;  // the target's frame; see BM_RenderObscurance
  double gpuMs = 0;
  for (auto _ : state) {
    const aal::FrameResult frame = f.renderer->render(*f.scene, f.settings, false);
    for (const auto& pass : frame.passMilliseconds) gpuMs += pass.second;
  }
  state.counters["gpu_ms"] = gpuMs / static_cast<double>(state.iterations());
  state.SetLabel(state.range(0) == 0   ? "approx"
                 : state.range(0) == 1 ? "exact"
                 : state.range(0) == 2 ? "baseline-lambert"
                 : state.range(0) == 3 ? "baseline-ao"
                                       : "horizon");
}
// CPU time: the whole process's (lavapipe's threads shade the frame), less
// sensitive than wall time to other processes on a shared machine
// (scripts/bench-horizon-ab.sh compares it).
BENCHMARK(BM_RenderFrame)
    ->DenseRange(0, 3)
    ->Arg(AAL_MODE_HORIZON)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The approx frame (framed view, no obscurance) with at most N probes of
// the footprint filtering (FrameSettings::anisotropy, 1..4): what each probe
// costs. Compare in one run, interleaved:
//   bench_render --benchmark_filter='RenderAnisotropy' --benchmark_repetitions=5
//     --benchmark_enable_random_interleaving=true
void BM_RenderAnisotropy(benchmark::State& state) {
  Fixture& f = fixture();
  aal::FrameSettings s = f.settings;
  s.mode = aal::ShadingMode::Approx;
  s.obscurance.enabled = false;
  s.anisotropy = static_cast<int>(state.range(0));
  for (auto _ : state) f.renderer->render(*f.scene, s, false);
}
BENCHMARK(BM_RenderAnisotropy)
    ->DenseRange(1, aal::kMaxFootprintProbes)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The frame over jacksboro from three views (0: the framed start
// view, 1: a flight 1.2 km above the ground looking ahead, 2: a lower one
// in the middle of the DEM) with and without the obscurance passes, at a
// geometric error of 1, 2, 4 (the default) and 8 pixels. The per-pass GPU
// times of lavapipe are not reliable (it rasterizes when a rendering ends):
// compare wall times, interleaved, e.g.
//   bench_render --benchmark_filter='RenderView/.*/4' --benchmark_repetitions=5
//     --benchmark_enable_random_interleaving=true
void BM_RenderView(benchmark::State& state) {
  Fixture& f = fixture();
  aal::FrameSettings s = f.settings;
  if (state.range(0) == 1) {
    s.camera.position = {-12000, -12000, 1800};
    s.camera.lookAt = {-9000, -9000, 1200};
  } else if (state.range(0) == 2) {
    s.camera.position = {-2000, -2000, 1500};
    s.camera.lookAt = {1000, 1000, 900};
  }
  s.obscurance.enabled = state.range(1) != 0;
  s.lod.maxErrorPixels = double(state.range(2));
  double triangles = 0;
  for (auto _ : state) triangles += double(f.renderer->render(*f.scene, s, false).triangles);
  state.counters["triangles"] = triangles / static_cast<double>(state.iterations());
}
BENCHMARK(BM_RenderView)
    ->ArgsProduct({{0, 1, 2}, {0, 1}, {1, 2, 4, 8}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

// The approx frame with the obscurance passes for n = 0 (off), 8,
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

// The quadtree LOD flying over synthetic fBm DEMs of 1024^2 to
// 16384^2 texels (30 m cells; made in memory, never stored), 1280x720, the
// approx frame without the obscurance passes, the default 2 M triangle
// budget. The scene has an open sky for apertures (the map's content does
// not change the frame time) and nothing is baked. DEMs beyond one image of
// the device are tiled (engine/terrain_tiles.h: on lavapipe 16384^2 is, its
// RGBA16F aperture alone being a 2 GiB allocation). The camera flies the
// same world path over every DEM: 24 km diagonally through the centre, 300 m
// above the ground, looking 3 km ahead; each iteration renders the next of 16
// points on it. Target: the largest DEM within 1.5x of the smallest. On a
// shared machine compare a small and a big DEM in one run, alternated:
//   bench_render --benchmark_filter='LodFlight/(1024|16384)/0/'
//     --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
// The second argument forces tiles of at most that many texels (0: only the
// device's limits): LodFlight/8192/4096 is 8192/0 in 2x2 tiles, the cost of
// the tiling itself. AAL_BENCH_LOD_SIZE=N adds an N^2 DEM (e.g. 20000 or
// 24576; about 16 bytes per texel of memory on lavapipe, where device
// memory is host memory, plus the 1024^2 DEM and the renderer).
struct LodFixture {
  aal::Heightfield field;
  std::unique_ptr<aal::TerrainScene> scene;
};

aal::Device& benchDevice() {
  return fixture().device;
}

// `maxTileTexels` > 0 forces tiles of at most that size (TerrainTiling), to
// compare a tiled DEM with the same DEM in one image.
LodFixture& lodFixture(int size, uint32_t maxTileTexels) {
  static std::map<std::pair<int, uint32_t>, LodFixture> fixtures;
  const std::pair<int, uint32_t> key(size, maxTileTexels);
  auto it = fixtures.find(key);
  if (it != fixtures.end()) return it->second;
  // One big DEM size at a time (memory); the small ones stay, so
  // --benchmark_enable_random_interleaving can alternate a small and a big one.
  std::erase_if(fixtures,
                [&](const auto& f) { return f.first.first > 4096 && f.first.first != size; });
  LodFixture& f = fixtures[key];
  aal::SyntheticTerrainOptions o;
  o.width = o.height = size;
  f.field = aal::makeSyntheticTerrain(o);
  f.scene = std::make_unique<aal::TerrainScene>(benchDevice(), f.field, nullptr, 2'000'000,
                                                aal::TerrainTiling{maxTileTexels, 0});
  return f;
}

void BM_RenderLodFlight(benchmark::State& state) {
  Fixture& base = fixture();
  LodFixture& f = lodFixture(static_cast<int>(state.range(0)),
                             state.range(1) > 0 ? static_cast<uint32_t>(state.range(1)) : 0);
  aal::FrameSettings s = base.settings;
  s.mode = aal::ShadingMode::Approx;
  s.obscurance.enabled = false;
  s.camera.verticalFovDeg = 40;
  const auto groundAt = [&](double x, double y) {
    const int col =
        std::clamp(int(x / f.field.cellSizeXM + 0.5 * (f.field.width - 1)), 0, f.field.width - 1);
    const int row =
        std::clamp(int(0.5 * (f.field.height - 1) - y / f.field.cellSizeYM), 0, f.field.height - 1);
    return double(f.field.at(col, row));
  };
  double gpuMs = 0, triangles = 0;
  int point = 0;
  for (auto _ : state) {
    const double t = -12000.0 + 24000.0 * (point++ % 16) / 15.0;
    const glm::dvec3 position(t, t, groundAt(t, t) + 300.0);
    s.camera.position = position;
    s.camera.lookAt = {t + 2121.0, t + 2121.0, groundAt(t + 2121.0, t + 2121.0)};
    const aal::FrameResult frame = base.renderer->render(*f.scene, s, false);
    for (const auto& pass : frame.passMilliseconds) gpuMs += pass.second;
    triangles += static_cast<double>(frame.triangles);
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["gpu_ms"] = gpuMs / n;
  state.counters["triangles"] = triangles / n;
  state.counters["tiles"] = f.scene->tiles().tileCount();
  state.counters["texture_mib"] = double(f.scene->textureBytes()) / (1 << 20);
}
BENCHMARK(BM_RenderLodFlight)
    ->Args({1024, 0})
    ->Args({8192, 0})
    ->Args({8192, 4096})
    ->Args({16384, 0})
    ->Iterations(16)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  if (const char* size = std::getenv("AAL_BENCH_LOD_SIZE")) {
    benchmark::RegisterBenchmark("BM_RenderLodFlight", BM_RenderLodFlight)
        ->Args({std::atoi(size), 0})
        ->Iterations(16)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
