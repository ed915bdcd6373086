// Aperture map file I/O: writing a 1024^2 and a 4096^2 map as
// halves, and reading them back whole (floats) and in row bands (halves, as
// the renderer streams them). The map is a real bake of a synthetic fBm DEM, so the
// compression sees bake-like data. Figures: docs/performance.md.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/synthetic.h"

namespace {

constexpr int kBandRows = 256;

// A size x size bake, made once per size.
const aal::ApertureMap& bakedMap(int size) {
  static std::map<int, aal::ApertureMap> maps;
  auto found = maps.find(size);
  if (found != maps.end()) return found->second;
  aal::SyntheticTerrainOptions s;
  s.width = s.height = size;
  s.cellSizeM = 30;
  s.amplitudeM = 800;
  s.featureSizeTexels = size / 4.0;
  s.octaves = 8;
  aal::BakeOptions options;
  options.azimuths = 16;
  aal::ApertureMap baked = aal::bakeApertures(aal::makeSyntheticTerrain(s), options).aperture;
  baked.info.source = "bench.tif";
  return maps.emplace(size, std::move(baked)).first->second;
}

std::string mapPath(int size) {
  return (std::filesystem::temp_directory_path() /
          ("aal_bench_aperture_map_" + std::to_string(size) + ".exr"))
      .string();
}

// The map on disk, written once per size for the reading benchmarks.
const std::string& writtenMap(int size) {
  static std::map<int, std::string> paths;
  auto found = paths.find(size);
  if (found != paths.end()) return found->second;
  aal::writeApertureMap(mapPath(size), bakedMap(size), true);
  return paths.emplace(size, mapPath(size)).first->second;
}

void BM_WriteApertureMapHalf(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const aal::ApertureMap& map = bakedMap(size);
  for (auto _ : state) aal::writeApertureMap(mapPath(size), map, true);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(mapPath(size)));
}
BENCHMARK(BM_WriteApertureMapHalf)
    ->Arg(1024)
    ->Arg(4096)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_ReadApertureMap(benchmark::State& state) {
  const std::string& path = writtenMap(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    aal::ApertureMap map = aal::readApertureMap(path);
    benchmark::DoNotOptimize(map.texels.data());
  }
}
BENCHMARK(BM_ReadApertureMap)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadApertureMapHalfRows(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const std::string& path = writtenMap(size);
  std::vector<uint16_t> halves(static_cast<size_t>(size) * size * 4);
  for (auto _ : state) {
    aal::ApertureMapReader reader(path);
    for (int row = 0; row < size; row += kBandRows) {
      reader.readHalfRows(row, std::min(size, row + kBandRows),
                          halves.data() + static_cast<size_t>(row) * size * 4);
    }
    benchmark::DoNotOptimize(halves.data());
  }
}
BENCHMARK(BM_ReadApertureMapHalfRows)
    ->Arg(1024)
    ->Arg(4096)
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
