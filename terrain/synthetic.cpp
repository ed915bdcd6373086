#include "aperture/terrain/synthetic.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>

namespace aal {

namespace {

// SplitMix64-style integer hash of a lattice point: the same value on every
// platform, unlike std:: distributions.
double latticeValue(int64_t x, int64_t y, uint64_t seed) {
  uint64_t h = seed * 0x9E3779B97F4A7C15ull ^ static_cast<uint64_t>(x) * 0xBF58476D1CE4E5B9ull ^
               static_cast<uint64_t>(y) * 0x94D049BB133111EBull;
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBull;
  h ^= h >> 31;
  return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;  // [-1, 1)
}

double smootherstep(double t) {
  return t * t * t * (t * (t * 6 - 15) + 10);
}

// Value noise in [-1, 1] with C2-continuous interpolation.
double valueNoise(double x, double y, uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  const double tx = smootherstep(x - fx), ty = smootherstep(y - fy);
  const double a = latticeValue(ix, iy, seed), b = latticeValue(ix + 1, iy, seed);
  const double c = latticeValue(ix, iy + 1, seed), d = latticeValue(ix + 1, iy + 1, seed);
  return (a + (b - a) * tx) + ((c + (d - c) * tx) - (a + (b - a) * tx)) * ty;
}

}  // namespace

Heightfield makeSyntheticTerrain(const SyntheticTerrainOptions& o) {
  if (o.width <= 0 || o.height <= 0 || o.cellSizeM <= 0 || o.octaves <= 0 ||
      o.featureSizeTexels <= 0) {
    throw std::invalid_argument("synthetic terrain needs positive size, cell size and octaves");
  }
  Heightfield field;
  field.width = o.width;
  field.height = o.height;
  field.cellSizeXM = field.cellSizeYM = o.cellSizeM;
  field.format = "synthetic";
  field.source = std::string(o.ridged ? "ridged" : "fBm") + " seed " + std::to_string(o.seed);
  field.z.resize(field.texelCount());

  tbb::parallel_for(0, o.height, [&](int y) {
    for (int x = 0; x < o.width; ++x) {
      double sum = 0, amplitude = 1, norm = 0, frequency = 1.0 / o.featureSizeTexels;
      for (int octave = 0; octave < o.octaves; ++octave) {
        double n = valueNoise(x * frequency, y * frequency, o.seed + octave * 1013);
        if (o.ridged) n = 1.0 - 2.0 * std::abs(n);  // sharp crests, in [-1, 1]
        sum += amplitude * n;
        norm += amplitude;
        amplitude *= 0.5;
        frequency *= 2.0;
      }
      field.z[field.index(x, y)] = static_cast<float>(0.5 * o.amplitudeM * (sum / norm + 1.0));
    }
  });
  return field;
}

}  // namespace aal
