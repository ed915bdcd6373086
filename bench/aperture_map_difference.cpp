// Compares two aperture maps of the same DEM (files or tile folders): the
// visible fraction's absolute difference (mean, 99th percentile, max) and
// the angle between the bent normals (mean, 99th percentile, max), and the
// share of texels where OTHER sees more sky (a lower horizon) by more than
// 0.001: the figures docs/baking.md gives for the far field of tiled bakes.
//   bench_aperture_map_difference REFERENCE OTHER
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <vector>

#include "aperture/terrain/io/aperture_map.h"

namespace {

double percentile(std::vector<double>& values, double p) {
  const size_t k = std::min(values.size() - 1, static_cast<size_t>(p * values.size()));
  std::nth_element(values.begin(), values.begin() + static_cast<ptrdiff_t>(k), values.end());
  return values[k];
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s REFERENCE OTHER\n", argv[0]);
    return 2;
  }
  try {
    const aal::ApertureMap a = aal::readApertureMap(argv[1]);
    const aal::ApertureMap b = aal::readApertureMap(argv[2]);
    if (a.width != b.width || a.height != b.height) {
      std::fprintf(stderr, "the maps differ in size\n");
      return 2;
    }
    const size_t n = a.texelCount();
    std::vector<double> visible(n), angle(n);
    double visibleSum = 0.0, angleSum = 0.0;
    size_t moreSky = 0;  // OTHER's visible fraction above REFERENCE's by more than 0.001
    for (size_t i = 0; i < n; ++i) {
      const double difference = double(b.visibleFraction(i)) - a.visibleFraction(i);
      visible[i] = std::abs(difference);
      if (difference > 1e-3) ++moreSky;
      const float* p = &a.texels[4 * i];
      const float* q = &b.texels[4 * i];
      const double dot = double(p[0]) * q[0] + double(p[1]) * q[1] + double(p[2]) * q[2];
      const double lengths =
          std::sqrt((double(p[0]) * p[0] + double(p[1]) * p[1] + double(p[2]) * p[2]) *
                    (double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2]));
      angle[i] = std::acos(std::clamp(dot / lengths, -1.0, 1.0)) * 180.0 / std::numbers::pi;
      visibleSum += visible[i];
      angleSum += angle[i];
    }
    const double visibleMax = *std::max_element(visible.begin(), visible.end());
    const double angleMax = *std::max_element(angle.begin(), angle.end());
    std::printf(
        "texels %zu\nvisible fraction |difference|: mean %.6f, p99 %.6f, max %.6f\n"
        "bent-normal angle (degrees): mean %.4f, p99 %.4f, max %.3f\n"
        "texels where OTHER sees more sky by > 0.001: %.4f %%\n",
        n, visibleSum / n, percentile(visible, 0.99), visibleMax, angleSum / n,
        percentile(angle, 0.99), angleMax, 100.0 * moreSky / n);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
