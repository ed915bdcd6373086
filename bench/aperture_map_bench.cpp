// Aperture map file I/O (issue 16): writing a 4096^2 map as halves, and
// reading it back whole (floats) and in row bands (halves, as the renderer
// streams it). The map is a real bake of a synthetic fBm DEM, so the
// compression sees bake-like data. Figures: docs/performance.md.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>
#include <vector>

#include "aperture_map.h"
#include "bake.h"
#include "synthetic.h"

namespace {

constexpr int kSize = 4096;
constexpr int kBandRows = 256;

const aal::ApertureMap& bakedMap() {
  static const aal::ApertureMap map = [] {
    aal::SyntheticTerrainOptions s;
    s.width = s.height = kSize;
    s.cellSizeM = 30;
    s.amplitudeM = 800;
    s.featureSizeTexels = kSize / 4.0;
    s.octaves = 8;
    aal::BakeOptions options;
    options.azimuths = 16;
    aal::ApertureMap baked = aal::bakeApertures(aal::makeSyntheticTerrain(s), options).aperture;
    baked.info.source = "bench.tif";
    return baked;
  }();
  return map;
}

std::string mapPath() {
  return (std::filesystem::temp_directory_path() / "aal_bench_aperture_map.exr").string();
}

// The map on disk, written once for the reading benchmarks.
const std::string& writtenMap() {
  static const std::string path = [] {
    aal::writeApertureMap(mapPath(), bakedMap(), true);
    return mapPath();
  }();
  return path;
}

void BM_WriteApertureMapHalf(benchmark::State& state) {
  const aal::ApertureMap& map = bakedMap();
  for (auto _ : state) aal::writeApertureMap(mapPath(), map, true);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(mapPath()));
}
BENCHMARK(BM_WriteApertureMapHalf)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadApertureMap(benchmark::State& state) {
  const std::string& path = writtenMap();
  for (auto _ : state) {
    aal::ApertureMap map = aal::readApertureMap(path);
    benchmark::DoNotOptimize(map.texels.data());
  }
}
BENCHMARK(BM_ReadApertureMap)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadApertureMapHalfRows(benchmark::State& state) {
  const std::string& path = writtenMap();
  std::vector<uint16_t> halves(static_cast<size_t>(kSize) * kSize * 4);
  for (auto _ : state) {
    aal::ApertureMapReader reader(path);
    for (int row = 0; row < kSize; row += kBandRows) {
      reader.readHalfRows(row, row + kBandRows,
                          halves.data() + static_cast<size_t>(row) * kSize * 4);
    }
    benchmark::DoNotOptimize(halves.data());
  }
}
BENCHMARK(BM_ReadApertureMapHalfRows)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
