#include "obscurance_samples.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <random>
#include <stdexcept>
#include <string>

namespace aal {

namespace {

constexpr double kTwoPi = 6.28318530717958647692;
// Lloyd relaxation: Voronoi cells estimated from this many candidate points
// per site, and this many iterations (the site moves stop changing the
// minimum distance after ~30).
constexpr int kCandidatesPerSite = 1024;
constexpr int kLloydIterations = 40;

// Radical inverse in base b of i: the Halton sequence's coordinates.
double radicalInverse(uint32_t i, uint32_t base) {
  double result = 0, scale = 1.0 / base;
  for (; i > 0; i /= base, scale /= base) result += (i % base) * scale;
  return result;
}

// ξx wraps (azimuth); ξy and ξz do not.
double wrapped(double dx) {
  return dx - std::round(dx);
}

double periodicDistance2(const glm::dvec3& a, const glm::dvec3& b) {
  const double dx = wrapped(a.x - b.x), dy = a.y - b.y, dz = a.z - b.z;
  return dx * dx + dy * dy + dz * dz;
}

std::vector<glm::vec3> relaxedPoints(int n) {
  // Start from uniform random sites: deterministic, since mt19937's output is
  // fixed by the standard and the conversion to [0, 1) is ours.
  std::mt19937 rng(static_cast<uint32_t>(n));
  auto unit = [&] { return static_cast<double>(rng() >> 8) * 0x1p-24; };
  std::vector<glm::dvec3> sites(static_cast<size_t>(n));
  for (glm::dvec3& s : sites) s = {unit(), unit(), unit()};

  // Candidates: the 3D Halton sequence (bases 2, 3, 5), well spread itself,
  // so the cell centroids are accurate with few candidates.
  std::vector<glm::dvec3> candidates(static_cast<size_t>(n) * kCandidatesPerSite);
  for (size_t i = 0; i < candidates.size(); ++i) {
    const uint32_t k = static_cast<uint32_t>(i + 1);
    candidates[i] = {radicalInverse(k, 2), radicalInverse(k, 3), radicalInverse(k, 5)};
  }

  std::vector<glm::dvec3> sum(sites.size());
  std::vector<int> count(sites.size());
  for (int iteration = 0; iteration < kLloydIterations; ++iteration) {
    std::fill(sum.begin(), sum.end(), glm::dvec3(0.0));
    std::fill(count.begin(), count.end(), 0);
    for (const glm::dvec3& c : candidates) {
      size_t nearest = 0;
      double best = std::numeric_limits<double>::max();
      for (size_t s = 0; s < sites.size(); ++s) {
        const double d2 = periodicDistance2(c, sites[s]);
        if (d2 < best) best = d2, nearest = s;
      }
      // Accumulate x relative to the site so a cell across the wrap averages
      // correctly.
      const glm::dvec3& site = sites[nearest];
      sum[nearest] += glm::dvec3(site.x + wrapped(c.x - site.x), c.y, c.z);
      ++count[nearest];
    }
    for (size_t s = 0; s < sites.size(); ++s) {
      if (count[s] == 0) continue;
      glm::dvec3 centroid = sum[s] / static_cast<double>(count[s]);
      centroid.x -= std::floor(centroid.x);
      sites[s] = centroid;
    }
  }
  std::vector<glm::vec3> points;
  points.reserve(sites.size());
  for (const glm::dvec3& s : sites) points.emplace_back(s);
  return points;
}

void checkCount(int n) {
  if (!isSupportedObscuranceSampleCount(n)) {
    throw std::invalid_argument("obscurance sample count must be 8, 16 or 32, got " +
                                std::to_string(n));
  }
}

}  // namespace

bool isSupportedObscuranceSampleCount(int n) {
  return n == 8 || n == 16 || n == 32;
}

const std::vector<glm::vec3>& obscuranceUnitCubePoints(int n) {
  checkCount(n);
  static std::mutex mutex;
  static std::map<int, std::vector<glm::vec3>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, relaxedPoints(n)).first;
  return it->second;
}

glm::vec3 obscuranceOffset(glm::vec3 xi) {
  const double phi = kTwoPi * xi.x;
  const double sinTheta = std::sqrt(static_cast<double>(xi.y));
  const double cosTheta = std::sqrt(std::max(0.0, 1.0 - static_cast<double>(xi.y)));
  const double r = static_cast<double>(xi.z) * xi.z;  // μ⁻¹(ξz) / R
  return glm::vec3(glm::dvec3(std::cos(phi) * sinTheta, std::sin(phi) * sinTheta, cosTheta) * r);
}

const std::vector<glm::vec3>& obscuranceSampleOffsets(int n) {
  checkCount(n);
  static std::mutex mutex;
  static std::map<int, std::vector<glm::vec3>> cache;
  const std::vector<glm::vec3>& points = obscuranceUnitCubePoints(n);
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(n);
  if (it == cache.end()) {
    std::vector<glm::vec3> offsets;
    offsets.reserve(points.size());
    for (const glm::vec3& p : points) offsets.push_back(obscuranceOffset(p));
    it = cache.emplace(n, std::move(offsets)).first;
  }
  return it->second;
}

double minimumPeriodicDistance(const std::vector<glm::vec3>& points) {
  double best = std::numeric_limits<double>::max();
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = i + 1; j < points.size(); ++j) {
      best = std::min(best, periodicDistance2(points[i], points[j]));
    }
  }
  return std::sqrt(best);
}

double l2StarDiscrepancy(const std::vector<glm::vec3>& points) {
  // Warnock: T² = 3^-d - 2^(1-d)/n Σ_i Π_k (1 - x_ik²)
  //             + 1/n² Σ_i Σ_j Π_k (1 - max(x_ik, x_jk)), d = 3.
  const double n = static_cast<double>(points.size());
  double single = 0, pair = 0;
  for (const glm::vec3& p : points) {
    const glm::dvec3 x(p);
    single += (1 - x.x * x.x) * (1 - x.y * x.y) * (1 - x.z * x.z);
    for (const glm::vec3& q : points) {
      const glm::dvec3 y(q);
      pair += (1 - std::max(x.x, y.x)) * (1 - std::max(x.y, y.y)) * (1 - std::max(x.z, y.z));
    }
  }
  const double t2 = 1.0 / 27.0 - 0.25 / n * single + pair / (n * n);
  return std::sqrt(std::max(0.0, t2));
}

}  // namespace aal
