#include "aperture/preprocess/local_dominance.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include "aperture/preprocess/bake.h"

namespace aal {

namespace {

// RVT's azimuths: every 15 degrees.
constexpr int kAzimuthStepDeg = 15;

// One sample of the ring: its offset in cells and its weight, the ring's
// area at its distance over the distance, (2d + 1) / d.
struct RingSample {
  int dCol, dRow;
  double weight;
};

std::vector<RingSample> ringSamples(const LocalDominanceOptions& o) {
  std::vector<RingSample> samples;
  for (int azimuth = 0; azimuth < 360; azimuth += kAzimuthStepDeg) {
    const double a = azimuth * std::numbers::pi / 180.0;
    for (int d = o.minRadiusCells; d <= o.maxRadiusCells; ++d) {
      samples.push_back({static_cast<int>(std::lround(d * std::cos(a))),
                         static_cast<int>(std::lround(d * std::sin(a))), (2.0 * d + 1.0) / d});
    }
  }
  return samples;
}

}  // namespace

void checkLocalDominanceOptions(const LocalDominanceOptions& o) {
  if (o.minRadiusCells < 1 || o.minRadiusCells > o.maxRadiusCells || o.maxRadiusCells > 1000) {
    throw std::invalid_argument("local dominance radii must satisfy 1 <= min <= max <= 1000 cells");
  }
  if (!(o.observerHeightM > 0.0) || !std::isfinite(o.observerHeightM)) {
    throw std::invalid_argument("local dominance observer height must be > 0 metres");
  }
}

std::vector<float> localDominance(const Heightfield& field, const LocalDominanceOptions& o) {
  checkLocalDominanceOptions(o);
  const std::vector<RingSample> samples = ringSamples(o);
  // A plane's sum: the observer looks down on every sample by h / d.
  double plane = 0.0;
  for (const RingSample& s : samples) plane += s.weight * o.observerHeightM;
  // Away from the edges a sample is a fixed offset in the heights: no clamping.
  std::vector<ptrdiff_t> offsets;
  for (const RingSample& s : samples) offsets.push_back(ptrdiff_t(s.dRow) * field.width + s.dCol);
  const int reach = o.maxRadiusCells;
  std::vector<float> out(field.texelCount());
  tbb::parallel_for(0, field.height, [&](int row) {
    // TBB carries the exception out of the parallel_for.
    if (o.cancel && o.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
    const bool rowInside = row >= reach && row + reach < field.height;
    for (int col = 0; col < field.width; ++col) {
      const size_t i = field.index(col, row);
      const double eye = double(field.z[i]) + o.observerHeightM;
      double sum = 0.0;
      if (rowInside && col >= reach && col + reach < field.width) {
        const float* centre = field.z.data() + i;
        for (size_t k = 0; k < samples.size(); ++k) {
          sum += samples[k].weight * std::max(0.0, eye - centre[offsets[k]]);
        }
      } else {
        for (const RingSample& s : samples) {
          const int c = std::clamp(col + s.dCol, 0, field.width - 1);
          const int r = std::clamp(row + s.dRow, 0, field.height - 1);
          sum += s.weight * std::max(0.0, eye - field.at(c, r));
        }
      }
      out[i] = static_cast<float>(sum / plane);
    }
  });
  return out;
}

}  // namespace aal
