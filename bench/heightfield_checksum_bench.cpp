// The heights checksum (aal:sourceChecksum, docs/baking.md "Heights
// checksum") on an N x N field: version 1, the byte-serial FNV-1a of older
// maps, against version 2, the row hash, on 1 thread and on all cores.
// bench_heightfield_checksum --benchmark_filter=/8192 (docs/performance.md).
#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <thread>

#include "aperture/terrain/io/heightfield_checksum.h"
#include "aperture/terrain/synthetic.h"

namespace {

const aal::Heightfield& field(int size) {
  static aal::Heightfield cached;
  if (cached.width != size) {
    aal::SyntheticTerrainOptions s;
    s.width = s.height = size;
    s.seed = 1;
    cached = aal::makeSyntheticTerrain(s);
  }
  return cached;
}

void setBytes(benchmark::State& state, const aal::Heightfield& f) {
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(f.z.size() * sizeof(float)));
}

void BM_LegacyChecksum(benchmark::State& state) {
  const aal::Heightfield& f = field(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(aal::legacyHeightfieldChecksum(f));
  setBytes(state, f);
}

// range(1): threads, 0 for every core.
void BM_RowHashChecksum(benchmark::State& state) {
  const aal::Heightfield& f = field(static_cast<int>(state.range(0)));
  const size_t threads = state.range(1) > 0 ? static_cast<size_t>(state.range(1))
                                            : std::max(1u, std::thread::hardware_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
  for (auto _ : state) benchmark::DoNotOptimize(aal::heightfieldChecksum(f));
  setBytes(state, f);
}

BENCHMARK(BM_LegacyChecksum)->Arg(1024)->Arg(8192)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RowHashChecksum)
    ->Args({1024, 1})
    ->Args({1024, 0})
    ->Args({8192, 1})
    ->Args({8192, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
