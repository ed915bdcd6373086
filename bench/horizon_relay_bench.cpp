// The horizon mode's re-lay (TerrainScene::relayHorizons): the horizons of
// another pair of directions written into the slope texture when the sun
// leaves the pair on the device (docs/rendering.md, the horizon mode), which
// the viewer pays as a hitch in one frame: the pair's codes made on the
// host from the kept map and uploaded (2 B per texel), and the compute pass
// that decodes them and makes their mip levels (with the slopes, again).
// Synthetic DEMs of 1024^2 and 4096^2 texels with an open sky for apertures
// (neither the heights nor the codes change the time; random codes),
// horizons of 8 directions of 8 bits and 16 of 4 bits. Each iteration
// re-lays once, alternating two pairs. Wall time: the re-lay waits for the
// device (lavapipe: copies and the compute pass on the CPU).
//   bench_horizon_relay --benchmark_repetitions=5
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>
#include <tuple>
#include <utility>

#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/synthetic.h"

namespace {

struct RelayFixture {
  aal::Heightfield field;
  std::unique_ptr<aal::TerrainScene> scene;
};

aal::Device& device() {
  static aal::Instance instance;
  static aal::Device d(instance);
  return d;
}

// One fixture at a time (a 4096^2 scene with 16 B per texel of horizons'
// host codes is about 1 GB).
RelayFixture& relayFixture(int size, int directions, int bits) {
  static std::map<std::tuple<int, int, int>, RelayFixture> fixtures;
  const auto key = std::make_tuple(size, directions, bits);
  auto it = fixtures.find(key);
  if (it != fixtures.end()) return it->second;
  fixtures.clear();
  RelayFixture& f = fixtures[key];
  aal::SyntheticTerrainOptions o;
  o.width = o.height = size;
  f.field = aal::makeSyntheticTerrain(o);
  f.scene = std::make_unique<aal::TerrainScene>(device(), f.field, nullptr, 2'000'000);
  auto map = std::make_shared<aal::HorizonMap>();
  map->width = map->height = size;
  map->directions = directions;
  map->bits = bits;
  map->codes.resize(size_t(size) * size_t(size) * size_t(directions));
  std::mt19937 rng(18);
  std::uniform_int_distribution<int> code(0, (1 << bits) - 1);
  for (uint8_t& c : map->codes) c = uint8_t(code(rng));
  f.scene->setHorizons(device(), std::shared_ptr<const aal::HorizonMap>(std::move(map)), 0);
  return f;
}

// Arguments: DEM size, directions, bits.
void BM_RelayHorizons(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  RelayFixture& f =
      relayFixture(size, static_cast<int>(state.range(1)), static_cast<int>(state.range(2)));
  for (auto _ : state) {
    f.scene->relayHorizons(device(), 2 - f.scene->horizonFirst());
  }
  // The slope images the pass writes (level 0; the levels above add a third).
  uint64_t slopeBytes = 0;
  for (const aal::Image& page : f.scene->slopePages()) {
    slopeBytes += uint64_t{page.desc().width} * page.desc().height * page.desc().layers * 8;
  }
  state.counters["slopes_MiB"] = double(slopeBytes) / double(1 << 20);
}
BENCHMARK(BM_RelayHorizons)
    ->ArgsProduct({{1024, 4096}, {8}, {8}})
    ->ArgsProduct({{1024, 4096}, {16}, {4}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
