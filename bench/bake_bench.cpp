// Baking speed: the sweep on synthetic fBm DEMs. Targets (docs/performance.md,
// "Baking"; this 2-core machine): 1024^2 at 32 azimuths in <= 0.25 s (>= 1.3e8
// texel-azimuths/s). Larger sizes: scripts/bench-bake.sh.
#include <benchmark/benchmark.h>

#include <optional>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/tile_window_reader.h"
#include "aperture/preprocess/tiled_bake.h"
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

// A tile of a tiled bake read in windows (aal-bake --tile-size
// --low-memory): the centre 256^2 tile of a 1024^2 DEM, baked from its
// window (the tile and tileHalo around it), with a max distance in metres
// (state.range(0)) or, at 0, the far field.
void BM_BakeTileWindow(benchmark::State& state) {
  const aal::Heightfield field = terrain(1024);
  aal::BakeOptions options;
  options.azimuths = 32;
  options.maxDistanceM = static_cast<double>(state.range(0));
  aal::TiledBakeOptions tiled;
  tiled.tileSize = 256;
  std::optional<aal::HeightPyramid> pyramid;
  aal::FarField far;
  if (!(options.maxDistanceM > 0.0)) {
    pyramid.emplace(aal::buildHeightPyramid(field, aal::tiledBakePyramidShift(field, tiled)));
    far = aal::FarField{&*pyramid, aal::resolvedFarField(field, tiled)};
    options.farField = &far;
  }
  const aal::TexelWindow tile{384, 384, 256, 256};
  const int halo = aal::tileHalo(field, options, tiled);
  const aal::HeightWindow window = aal::windowOf(field, aal::tileReadWindow(field, halo, tile));
  for (auto _ : state) {
    aal::BakeResult result = aal::bakeApertureWindow(window, tile, options);
    benchmark::DoNotOptimize(result.aperture.texels.data());
  }
  state.counters["texel_azimuths_per_s"] = benchmark::Counter(
      double(tile.texelCount()) * options.azimuths, benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_BakeTileWindow)->Arg(3000)->Arg(0)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
