// The reference ray tracer's ray-terrain intersection (terrain_surface.h)
// against a brute-force march in steps of 1/512 of a cell.
#include "aperture/terrain/reference/terrain_surface.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <glm/geometric.hpp>

namespace aal {
namespace {

Heightfield randomField(int width, int height, double cellX, double cellY, uint32_t seed) {
  Heightfield f;
  f.width = width;
  f.height = height;
  f.cellSizeXM = cellX;
  f.cellSizeYM = cellY;
  f.format = "test";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> h(0.0f, 50.0f);
  f.z.resize(f.texelCount());
  for (float& z : f.z) z = h(rng);
  return f;
}

// The first sign change of z - h along the ray in steps of `step`, bisected;
// false if none before the ray leaves the footprint or sEnd.
bool marchedHit(const TerrainSurface& surface, const glm::dvec3& o, const glm::dvec3& d,
                double sStart, double sEnd, double step, double& sHit) {
  const auto f = [&](double s) {
    const glm::dvec3 p = o + s * d;
    return p.z - surface.heightAt(p.x, p.y);
  };
  const bool below = f(sStart) < 0;
  double previous = sStart;
  for (double s = sStart + step;; s += step) {
    const bool last = s >= sEnd;
    if (last) s = sEnd;
    const glm::dvec3 p = o + s * d;
    if (!surface.inside(p.x, p.y)) return false;
    if ((f(s) < 0) != below) {
      double lo = previous, hi = s;
      for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((f(mid) < 0) != below ? hi : lo) = mid;
      }
      sHit = hi;
      return true;
    }
    if (last) return false;
    previous = s;
  }
}

// Heightfield::bilinearHeight, which the march reads, takes differences of
// the float heights in float: 50 m heights are good to a few micrometres.
constexpr double kHeightRounding = 1e-5;

TEST(TerrainSurface, FirstCrossingMatchesAFineMarch) {
  const Heightfield field = randomField(17, 13, 10.0, 7.0, 5);
  const TerrainSurface surface(field);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x(-80, 80), y(-42, 42), z(-10, 70), angle(0, 6.2831853);
  std::uniform_real_distribution<double> slope(-0.8, 0.8);
  const double step = 7.0 / 512;
  int hits = 0, misses = 0;
  for (int ray = 0; ray < 3000; ++ray) {
    const glm::dvec3 o(x(rng), y(rng), z(rng));
    const double a = angle(rng);
    const glm::dvec3 d = glm::normalize(glm::dvec3(std::cos(a), std::sin(a), slope(rng)));
    double sExact = 0, sMarched = 0;
    const bool exact = surface.intersect(o, d, 0.0, 1e6, sExact);
    const bool marched = marchedHit(surface, o, d, 0.0, 1e6, step, sMarched);
    if (marched) {
      // The march can only miss a crossing (two within one step), never
      // find one the exact walk has not found first.
      ASSERT_TRUE(exact) << "ray " << ray;
      EXPECT_LE(sExact, sMarched + kHeightRounding) << "ray " << ray;
      if (sMarched - sExact > step) continue;  // a dip the march stepped over
      EXPECT_NEAR(sExact, sMarched, kHeightRounding) << "ray " << ray;
      ++hits;
    } else if (!exact) {
      ++misses;
    }
    if (exact) {
      const glm::dvec3 p = o + sExact * d;
      EXPECT_NEAR(p.z, surface.heightAt(p.x, p.y), kHeightRounding) << "ray " << ray;
    }
  }
  // Both kinds of ray were tried in numbers.
  EXPECT_GT(hits, 1000);
  EXPECT_GT(misses, 300);
}

TEST(TerrainSurface, AThinCrestStopsARayJustUnderIt) {
  // One column 80 m high on flat ground: the crest is a line, the ramps on
  // both sides 10 m wide. A level ray 0.5 m under the crest crosses the
  // ridge within 0.06 m: steps of half a cell went over it.
  Heightfield field = randomField(33, 9, 10.0, 10.0, 1);
  for (int row = 0; row < field.height; ++row) {
    for (int col = 0; col < field.width; ++col) field.z[field.index(col, row)] = col == 20 ? 80 : 0;
  }
  const TerrainSurface surface(field);
  double s = 0;
  ASSERT_TRUE(surface.intersect({-100, 0, 79.5}, {1, 0, 0}, 0, 1e6, s));
  EXPECT_NEAR(-100 + s, 40 - 0.5 / 8, 1e-9);  // x of the crest is (20 - 16) * 10 m
  EXPECT_FALSE(surface.intersect({-100, 0, 80.5}, {1, 0, 0}, 0, 1e6, s));
}

TEST(TerrainSurface, ARayFromBelowHitsWhereItComesUp) {
  Heightfield field = randomField(9, 9, 10.0, 10.0, 1);
  for (float& z : field.z) z = 100;
  const TerrainSurface surface(field);
  double s = 0;
  ASSERT_TRUE(surface.intersect({0, 0, 90}, glm::normalize(glm::dvec3(1, 0, 1)), 0, 1e6, s));
  EXPECT_NEAR(s, 10 * std::sqrt(2.0), 1e-9);
  // Leaving the footprint or the DEM's top escapes; so does starting outside.
  EXPECT_FALSE(surface.intersect({0, 0, 90}, {1, 0, 0}, 0, 1e6, s));
  EXPECT_FALSE(surface.intersect({0, 0, 110}, glm::normalize(glm::dvec3(1, 1, 0.1)), 0, 1e6, s));
  EXPECT_FALSE(surface.intersect({100, 0, 110}, {-1, 0, -1}, 0, 1e6, s));
  // sEnd bounds the search.
  EXPECT_FALSE(surface.intersect({0, 0, 90}, glm::normalize(glm::dvec3(1, 0, 1)), 0, 10, s));
}

}  // namespace
}  // namespace aal
