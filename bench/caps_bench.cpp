// Cost of one cap intersection on the CPU: exact vs Oat's approximation.
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include "aperture/terrain/light/caps.h"

namespace {

struct Triple {
  float r0, r1, d;
};

std::vector<Triple> randomTriples() {
  std::mt19937 rng(1);
  std::uniform_real_distribution<float> angle(0.0f, 3.14159265f);
  std::vector<Triple> t(4096);
  for (Triple& x : t) x = {angle(rng), angle(rng), angle(rng)};
  return t;
}

void BM_CapIntersectionExact(benchmark::State& state) {
  const auto triples = randomTriples();
  size_t i = 0;
  for (auto _ : state) {
    const Triple& t = triples[i++ & 4095];
    benchmark::DoNotOptimize(aal::capIntersectionExact(t.r0, t.r1, t.d));
  }
}
BENCHMARK(BM_CapIntersectionExact);

void BM_CapIntersectionApprox(benchmark::State& state) {
  const auto triples = randomTriples();
  size_t i = 0;
  for (auto _ : state) {
    const Triple& t = triples[i++ & 4095];
    benchmark::DoNotOptimize(aal::capIntersectionApprox(t.r0, t.r1, t.d));
  }
}
BENCHMARK(BM_CapIntersectionApprox);

}  // namespace

BENCHMARK_MAIN();
