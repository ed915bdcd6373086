// Small heightfields with known geometry for the baker tests.
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>

#include "aperture/terrain/heightfield.h"

namespace aal::test {

// A width x height field with square cells, heights from f(x, y) in world
// metres (origin at the DEM centre, x east, y north).
inline Heightfield makeField(int width, int height, double cellM,
                             const std::function<double(double, double)>& f) {
  Heightfield field;
  field.width = width;
  field.height = height;
  field.cellSizeXM = field.cellSizeYM = cellM;
  field.format = "test";
  field.z.resize(field.texelCount());
  for (int row = 0; row < height; ++row) {
    for (int col = 0; col < width; ++col) {
      const double x = (col - 0.5 * (width - 1)) * cellM;
      const double y = (0.5 * (height - 1) - row) * cellM;
      field.z[field.index(col, row)] = static_cast<float>(f(x, y));
    }
  }
  return field;
}

// Angle between two vectors in degrees, as atan2(|a x b|, a . b): accurate
// for tiny angles, where acos of the dot product of float unit vectors
// already reads 0.02 degrees for identical vectors.
inline double angleBetweenDeg(const float* a, const float* b) {
  const double cx = double(a[1]) * b[2] - double(a[2]) * b[1];
  const double cy = double(a[2]) * b[0] - double(a[0]) * b[2];
  const double cz = double(a[0]) * b[1] - double(a[1]) * b[0];
  const double dot = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2];
  return std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot) * 180.0 / std::numbers::pi;
}

// Tangent of the horizon seen from the centre of a square DEM of `size`
// texels (odd) and cell `cellM`, holding a conical pit with a flat bottom:
// z = k * max(0, r - r0). Looking in azimuth phi the walls rise steadily, so
// the horizon is the DEM edge: k (R - r0) / R, R the distance to the edge.
inline double flatPitHorizonTan(double k, double r0, int size, double cellM, double phi) {
  const double half = 0.5 * (size - 1) * cellM;
  const double edge = half / std::max(std::abs(std::cos(phi)), std::abs(std::sin(phi)));
  return k * (edge - r0) / edge;
}

inline double flatPit(double k, double r0, double x, double y) {
  return k * std::max(0.0, std::sqrt(x * x + y * y) - r0);
}

}  // namespace aal::test
