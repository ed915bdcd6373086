#include "aperture/preprocess/ray_bake.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <stdexcept>

#include <tbb/parallel_for.h>

namespace aal {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

uint64_t hashTexel(uint64_t i) {
  i += 0x9E3779B97F4A7C15ull;
  i = (i ^ (i >> 30)) * 0xBF58476D1CE4E5B9ull;
  i = (i ^ (i >> 27)) * 0x94D049BB133111EBull;
  return i ^ (i >> 31);
}

double nextUniform(uint64_t& state) {
  state = hashTexel(state);
  return static_cast<double>(state >> 11) / 9007199254740992.0;
}

}  // namespace

bool rayEscapes(const BakeTerrain& terrain, const BakeOptions& o, double x, double y, double z,
                const double dir[3], double zMax) {
  const Heightfield& f = *terrain.heights.dem;
  const double horizontal = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
  if (horizontal < 1e-12) return dir[2] > 0;
  const double rise = dir[2] / horizontal;  // metres up per metre along the ground
  const double ex = dir[0] / horizontal, ey = dir[1] / horizontal;
  const double curvature = o.curvature ? (1.0 - o.refraction) / (2.0 * kEarthRadiusM) : 0.0;
  const double step = 0.25 * std::min(terrain.cellY, terrain.rowCellX[f.height / 2]);

  const double rowCentre = 0.5 * (f.height - 1);
  // Fine steps near the start: the bilinear surface can rise above a ray
  // within the first fraction of a cell (at a texel the surface has a kink).
  for (double s = step / 64;; s += std::min(step, s)) {
    const double px = x + ex * s, py = y + ey * s;
    const double rayZ = z + rise * s;
    if (o.maxDistanceM > 0 && s > o.maxDistanceM) return true;
    // Above every terrain point and not coming down relative to the curved
    // ground: nothing further can block the ray.
    if (rayZ > zMax - curvature * s * s && rise + 2 * curvature * s >= 0) return true;
    const double row = rowCentre - py / terrain.cellY;
    const double rowClamped = std::clamp(row, 0.0, static_cast<double>(f.height - 1));
    const double cellX = terrain.rowCellX[static_cast<size_t>(std::lround(rowClamped))];
    const double col = terrain.centreCol + px / cellX;
    const bool outside = row < 0 || row > f.height - 1 || col < 0 || col > f.width - 1;
    if (outside && !o.clampEdge) return true;
    if (rayZ < f.bilinearHeight(col, row) - curvature * s * s) return false;
    if (s > 1e9) return true;  // numerically horizontal ray over a clamped plain
  }
}

void bakeRays(const BakeTerrain& terrain, const BakeOptions& o, float* sums,
              std::vector<float>& svf) {
  if (!svf.empty()) throw std::invalid_argument("the sky-view factor needs the sweep method");
  // The rays march the DEM's own heights (Heightfield::bilinearHeight).
  const Heightfield& f = *terrain.heights.dem;
  if (!terrain.window.covers(f) || f.z.size() != f.texelCount()) {
    throw std::invalid_argument("the ray method bakes whole fields only, not windows");
  }
  const double zMax = *std::max_element(f.z.begin(), f.z.end());
  const int azimuthStrata = std::max(1, static_cast<int>(std::lround(std::sqrt(o.rays * 2.0))));
  const int elevationStrata = std::max(1, o.rays / azimuthStrata);
  const int rays = azimuthStrata * elevationStrata;

  // Rows in blocks so that progress is reported here, on the calling
  // thread. Cancellation is polled per azimuth stratum as well: at 2^20 rays
  // a texel takes seconds (TBB carries the exception out of parallel_for).
  const auto checkCancel = [&] {
    if (o.cancel && o.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
  };
  const int block = std::max(1, f.height / 100);
  for (int first = 0; first < f.height; first += block) {
    checkCancel();
    const int last = std::min(f.height, first + block);
    tbb::parallel_for(first, last, [&](int row) {
      for (int col = 0; col < f.width; ++col) {
        const size_t i = f.index(col, row);
        // Tangent frame around the surface normal n = (-sx, -sy, 1)/|.|.
        const double sx = terrain.slopeEast(i), sy = terrain.slopeNorth(i);
        const double len = std::sqrt(1 + sx * sx + sy * sy);
        const double n[3] = {-sx / len, -sy / len, 1 / len};
        double t[3] = {n[2], 0, -n[0]};  // perpendicular to n in the x-z plane
        const double tl = std::sqrt(t[0] * t[0] + t[2] * t[2]);
        t[0] /= tl;
        t[2] /= tl;
        const double b[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2],
                             n[0] * t[1] - n[1] * t[0]};
        const double x = terrain.x(col, row), y = terrain.y(row), z = f.z[i];

        uint64_t rng = hashTexel(i);
        int escaped = 0;
        double sum[3] = {0, 0, 0};
        for (int a = 0; a < azimuthStrata; ++a) {
          checkCancel();
          for (int e = 0; e < elevationStrata; ++e) {
            // Uniform in solid angle: cos(theta) uniform in (0, 1].
            const double cosTheta = 1.0 - (e + nextUniform(rng)) / elevationStrata;
            const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
            const double phi = kTwoPi * (a + nextUniform(rng)) / azimuthStrata;
            const double lx = sinTheta * std::cos(phi), ly = sinTheta * std::sin(phi);
            const double dir[3] = {lx * t[0] + ly * b[0] + cosTheta * n[0],
                                   lx * t[1] + ly * b[1] + cosTheta * n[1],
                                   lx * t[2] + ly * b[2] + cosTheta * n[2]};
            if (rayEscapes(terrain, o, x, y, z, dir, zMax)) {
              ++escaped;
              sum[0] += dir[0];
              sum[1] += dir[1];
              sum[2] += dir[2];
            }
          }
        }
        float* s = sums + 4 * i;
        s[0] = static_cast<float>(sum[0]);
        s[1] = static_cast<float>(sum[1]);
        s[2] = static_cast<float>(sum[2]);
        s[3] = static_cast<float>(kTwoPi * escaped / rays);
      }
    });
    if (o.progress) o.progress(static_cast<double>(last) / f.height);
  }
}

}  // namespace aal
