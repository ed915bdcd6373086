#include "aperture/terrain/view/height_mips.h"

#include <algorithm>
#include <cmath>

#include <tbb/parallel_for.h>

namespace aal {

namespace {

int ceilDiv(int a, int b) {
  return (a + b - 1) / b;
}

}  // namespace

float HeightMips::Level::at(int k, int m) const {
  // Texels beyond the margin hold the same values as the margin's (all
  // their DEM texels are the repeated edge).
  k = std::clamp(k, -1, width - 2);
  m = std::clamp(m, -1, height - 2);
  return texels[size_t(m + 1) * size_t(width) + size_t(k + 1)];
}

HeightMips::HeightMips(const Heightfield& field, int levels) : field_(field) {
  for (int level = 1; level < levels; ++level) {
    Level next;
    // Texels -1 .. ceil(size / 2^l): the last and the margins lie wholly
    // beyond the DEM or before it.
    next.width = ceilDiv(field.width, 1 << level) + 2;
    next.height = ceilDiv(field.height, 1 << level) + 2;
    next.texels.resize(size_t(next.width) * size_t(next.height));
    const Level* above = levels_.empty() ? nullptr : &levels_.back();
    const auto source = [&](int k, int m) {
      if (above) return above->at(k, m);
      return field.at(std::clamp(k, 0, field.width - 1), std::clamp(m, 0, field.height - 1));
    };
    tbb::parallel_for(0, next.height, [&](int row) {
      const int m = row - 1;
      for (int column = 0; column < next.width; ++column) {
        const int k = column - 1;
        next.texels[size_t(row) * size_t(next.width) + size_t(column)] =
            meanOf2x2(source(2 * k, 2 * m), source(2 * k + 1, 2 * m), source(2 * k, 2 * m + 1),
                      source(2 * k + 1, 2 * m + 1));
      }
    });
    levels_.push_back(std::move(next));
  }
}

float HeightMips::at(int level, double column, double row) const {
  level = std::clamp(level, 0, static_cast<int>(levels_.size()));
  if (level == 0) return static_cast<float>(field_.bilinearHeight(column, row));
  const Level& l = levels_[size_t(level - 1)];
  const double scale = 1.0 / double(1 << level);
  // Level texel k's centre is DEM position (k + 0.5) 2^l - 0.5.
  const double x = (column + 0.5) * scale - 0.5, y = (row + 0.5) * scale - 0.5;
  const int k = static_cast<int>(std::floor(x)), m = static_cast<int>(std::floor(y));
  const double fx = x - k, fy = y - m;
  const double top = l.at(k, m) + (l.at(k + 1, m) - l.at(k, m)) * fx;
  const double bottom = l.at(k, m + 1) + (l.at(k + 1, m + 1) - l.at(k, m + 1)) * fx;
  return static_cast<float>(top + (bottom - top) * fy);
}

}  // namespace aal
