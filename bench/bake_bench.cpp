// Baking speed: the sweep on synthetic fBm DEMs. Targets (docs/performance.md,
// "Baking"; this 2-core machine): 1024^2 at 32 azimuths in <= 0.25 s (>= 1.3e8
// texel-azimuths/s). Larger sizes: scripts/bench-bake.sh.
#include <benchmark/benchmark.h>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/synthetic.h"

namespace {

aal::Heightfield terrain(int size) {
  aal::SyntheticTerrainOptions s;
  s.width = s.height = size;
  s.cellSizeM = 30;
  s.amplitudeM = 800;
  s.featureSizeTexels = size / 4.0;
  s.octaves = 8;
  return aal::makeSyntheticTerrain(s);
}

void BM_BakeSweep(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const int azimuths = static_cast<int>(state.range(1));
  const aal::Heightfield field = terrain(size);
  aal::BakeOptions options;
  options.azimuths = azimuths;
  for (auto _ : state) {
    aal::BakeResult result = aal::bakeApertures(field, options);
    benchmark::DoNotOptimize(result.aperture.texels.data());
  }
  const double texelAzimuths = double(size) * size * azimuths;
  state.counters["texel_azimuths_per_s"] =
      benchmark::Counter(texelAzimuths, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BakeSweep)
    ->Args({256, 32})
    ->Args({1024, 32})
    ->Args({1024, 64})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
