#include "aperture/terrain/light/obscurance_samples.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include <glm/common.hpp>

namespace aal {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Lloyd relaxation: Voronoi cells estimated from this many candidate points
// per site, and this many iterations (the site moves stop changing the
// minimum distance after ~30).
constexpr int kCandidatesPerSite = 1024;
constexpr int kLloydIterations = 40;
// Candidate (ξy, ξz) shifts tried for each interleave cell (cellShifts).
constexpr uint32_t kShiftCandidates = 1024;

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

// frac(p + shift) in [0, 1)^3 (the rounding to float must not give 1).
glm::vec3 toroidalShift(const glm::vec3& p, const glm::dvec3& shift) {
  glm::dvec3 q = glm::dvec3(p) + shift;
  q -= glm::floor(q);
  return glm::min(glm::vec3(q), glm::vec3(std::nextafter(1.0f, 0.0f)));
}

// The 16 Cranley-Patterson shifts of one set. s_k.x = k/16 keeps the
// azimuths of cell k those of rotation k. (s_k.y, s_k.z) are picked by
// best-candidate sampling (Mitchell 1991): for k = 1..15 in turn, of
// kShiftCandidates Halton (2, 3) shifts, the one whose shifted set lies
// furthest (minimum distance, ξx periodic) from the sets of cells 0..k-1.
// The 4x4 filter averages the 16 cells, so what it integrates with is their
// union of 16n points; this makes that union well spread too. Its minimum
// distance is 3.3-5.8x that of the rotations alone and 2-3x that with fixed
// shifts such as a (0,4,3)-net's, whose dyadic shifts map the n = 8 set
// nearly onto itself (docs/obscurance.md).
std::vector<glm::dvec3> cellShifts(const std::vector<glm::vec3>& points) {
  std::vector<glm::dvec3> shifts{glm::dvec3(0.0)};
  std::vector<glm::dvec3> placed(points.begin(), points.end());
  std::vector<glm::dvec3> shifted(points.size());
  for (int k = 1; k < kObscuranceSampleSets; ++k) {
    const double x = static_cast<double>(k) / kObscuranceSampleSets;
    double best = -1;
    glm::dvec3 bestShift(x, 0, 0);
    for (uint32_t c = 1; c <= kShiftCandidates; ++c) {
      const glm::dvec3 shift(x, radicalInverse(c, 2), radicalInverse(c, 3));
      double nearest = std::numeric_limits<double>::max();
      for (size_t i = 0; i < points.size() && nearest > best; ++i) {
        shifted[i] = glm::dvec3(toroidalShift(points[i], shift));
        for (const glm::dvec3& q : placed) {
          nearest = std::min(nearest, periodicDistance2(shifted[i], q));
        }
      }
      if (nearest > best) best = nearest, bestShift = shift;
    }
    shifts.push_back(bestShift);
    for (const glm::vec3& p : points) placed.emplace_back(toroidalShift(p, bestShift));
  }
  return shifts;
}

struct CellSets {
  std::vector<glm::vec3> shifts;
  std::vector<std::vector<glm::vec3>> points, offsets;  // per cell
};

const CellSets& cellSets(int n) {
  static std::mutex mutex;
  static std::map<int, CellSets> cache;
  const std::vector<glm::vec3>& points = obscuranceUnitCubePoints(n);
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(n);
  if (it == cache.end()) {
    CellSets sets;
    for (const glm::dvec3& shift : cellShifts(points)) {
      sets.shifts.emplace_back(shift);
      std::vector<glm::vec3> cellPoints, cellOffsets;
      for (const glm::vec3& p : points) {
        cellPoints.push_back(toroidalShift(p, shift));
        cellOffsets.push_back(obscuranceOffset(cellPoints.back()));
      }
      sets.points.push_back(std::move(cellPoints));
      sets.offsets.push_back(std::move(cellOffsets));
    }
    it = cache.emplace(n, std::move(sets)).first;
  }
  return it->second;
}

void checkCell(int cell) {
  if (cell < 0 || cell >= kObscuranceSampleSets) {
    throw std::invalid_argument("obscurance sample set must be 0..15, got " + std::to_string(cell));
  }
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

const std::vector<glm::vec3>& obscuranceCellShifts(int n) {
  checkCount(n);
  return cellSets(n).shifts;
}

const std::vector<glm::vec3>& obscuranceCellUnitCubePoints(int n, int cell) {
  checkCount(n);
  checkCell(cell);
  return cellSets(n).points[static_cast<size_t>(cell)];
}

const std::vector<glm::vec3>& obscuranceCellSampleOffsets(int n, int cell) {
  checkCount(n);
  checkCell(cell);
  return cellSets(n).offsets[static_cast<size_t>(cell)];
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

double wrapAroundL2Discrepancy(const std::vector<glm::vec3>& points) {
  // Hickernell 1998, eq. 5.1c: WD² = -(4/3)^d
  //     + 1/n² Σ_i Σ_j Π_k (3/2 - |x_ik - x_jk| (1 - |x_ik - x_jk|)), d = 3.
  const double n = static_cast<double>(points.size());
  double pair = 0;
  for (const glm::vec3& p : points) {
    for (const glm::vec3& q : points) {
      double product = 1;
      for (int k = 0; k < 3; ++k) {
        const double d = std::abs(static_cast<double>(p[k]) - q[k]);
        product *= 1.5 - d * (1 - d);
      }
      pair += product;
    }
  }
  const double wd2 = -64.0 / 27.0 + pair / (n * n);
  return std::sqrt(std::max(0.0, wd2));
}

}  // namespace aal
