#include "reference_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

namespace aal {

namespace {

constexpr double kPi = std::numbers::pi;

// The bilinear terrain in world metres, as the GPU sees it: uniform cells
// (the centre row's for geographic grids), heights clamped at the edges.
class TerrainSurface {
 public:
  explicit TerrainSurface(const Heightfield& field)
      : field_(field),
        cellX_(field.cellSizeXM),
        cellY_(field.cellSizeYM),
        halfX_(0.5 * (field.width - 1)),
        halfY_(0.5 * (field.height - 1)),
        maxHeight_(*std::max_element(field.z.begin(), field.z.end())),
        step_(0.5 * std::min(cellX_, cellY_)) {}

  bool inside(double x, double y) const {
    return std::abs(x) <= halfX_ * cellX_ + 1e-9 && std::abs(y) <= halfY_ * cellY_ + 1e-9;
  }

  double heightAtTexel(double col, double row) const { return field_.bilinearHeight(col, row); }

  double heightAt(double x, double y) const { return heightAtTexel(col(x), row(y)); }
  double col(double x) const { return x / cellX_ + halfX_; }
  double row(double y) const { return halfY_ - y / cellY_; }

  // Central differences one texel apart (shaders/terrain_shading.glsl surfaceNormal).
  glm::dvec3 normalAt(double x, double y) const {
    const double c = col(x), r = row(y);
    const double dx = heightAtTexel(c + 1, r) - heightAtTexel(c - 1, r);
    const double dy = heightAtTexel(c, r - 1) - heightAtTexel(c, r + 1);  // north is row - 1
    return glm::normalize(glm::dvec3(-dx / (2 * cellX_), -dy / (2 * cellY_), 1.0));
  }

  // First crossing of the surface by origin + s * dir for s in (sStart,
  // sEnd], by marching in steps of half a cell (horizontally and vertically)
  // and bisecting the last step. A ray that starts under the surface (one
  // entering the DEM's box through a side, below the edge) hits where it
  // comes up through it, as the GPU's two-sided triangles would show.
  // Leaving the DEM's box or rising above its top escapes.
  bool intersect(const glm::dvec3& origin, const glm::dvec3& dir, double sStart, double sEnd,
                 double& sHit) const {
    const double horizontal = std::hypot(dir.x, dir.y);
    const double ds = step_ / std::max({horizontal, std::abs(dir.z), 1e-9});
    const auto below = [&](double s) {
      const glm::dvec3 p = origin + s * dir;
      return p.z < heightAt(p.x, p.y);
    };
    const bool startsBelow = below(sStart);
    double sPrev = sStart;
    for (double s = sStart + ds;; s += ds) {
      const bool last = s >= sEnd;
      if (last) s = sEnd;
      const glm::dvec3 p = origin + s * dir;
      if (!inside(p.x, p.y)) return false;
      if (dir.z >= 0 && p.z > maxHeight_) return false;
      if (below(s) != startsBelow) {
        double lo = sPrev, hi = s;
        for (int i = 0; i < 20; ++i) {
          const double mid = 0.5 * (lo + hi);
          (below(mid) != startsBelow ? hi : lo) = mid;
        }
        sHit = hi;
        return true;
      }
      if (last) return false;
      sPrev = s;
    }
  }

  // The part [sIn, sOut] of origin + s * dir (s >= 0) inside the DEM's
  // footprint and below its top; false when there is none.
  bool clipToBox(const glm::dvec3& origin, const glm::dvec3& dir, double& sIn, double& sOut) const {
    sIn = 0;
    sOut = 1e300;
    const double lo[3] = {-halfX_ * cellX_, -halfY_ * cellY_, -1e300};
    // The top a hair above the highest texel, so that a ray entering through
    // it starts above the surface (a flat DEM's surface is its top).
    const double hi[3] = {halfX_ * cellX_, halfY_ * cellY_, maxHeight_ + 1e-3 * cell()};
    for (int a = 0; a < 3; ++a) {
      if (std::abs(dir[a]) < 1e-300) {
        if (origin[a] < lo[a] || origin[a] > hi[a]) return false;
        continue;
      }
      double s0 = (lo[a] - origin[a]) / dir[a], s1 = (hi[a] - origin[a]) / dir[a];
      if (s0 > s1) std::swap(s0, s1);
      sIn = std::max(sIn, s0);
      sOut = std::min(sOut, s1);
    }
    // A hair inside, so that the first sample is within the footprint.
    const double inset = 1e-9 * (1 + sIn);
    sIn += inset;
    sOut -= inset;
    return sIn < sOut;
  }
  double cell() const { return std::min(cellX_, cellY_); }

 private:
  const Heightfield& field_;
  double cellX_, cellY_, halfX_, halfY_, maxHeight_, step_;
};

// An orthonormal frame around n (Duff et al. 2017, "Building an Orthonormal
// Basis, Revisited").
void frameAround(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = {1 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

// Stratified samples on a k x k grid of the unit square (k = ceil(sqrt(n)),
// the first n strata), jittered.
template <class Rng>
glm::dvec2 stratified(int i, int n, Rng& rng) {
  const int k = static_cast<int>(std::ceil(std::sqrt(double(n))));
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return {((i % k) + u(rng)) / k, ((i / k) + u(rng)) / k};
}

class PixelShader {
 public:
  PixelShader(const TerrainSurface& surface, const ReferenceSettings& s)
      : surface_(surface),
        s_(s),
        sun_(glm::normalize(glm::dvec3(s.lighting.sunDirection))),
        cosSunRadius_(std::cos(double(s.lighting.sunRadiusRad))) {
    frameAround(sun_, sunT_, sunB_);
  }

  glm::dvec3 shade(const glm::dvec3& p, std::mt19937& rng) const {
    const glm::dvec3 n = surface_.normalAt(p.x, p.y);
    const glm::dvec3 albedo(s_.albedo);
    const glm::dvec3 origin = p + n * (1e-3 * surface_.cell());
    const double start = 1e-3 * surface_.cell();
    const double far = 1e12;

    // Sun: uniform points of the disk (uniform in solid angle on the cap).
    double sunSum = 0;
    for (int i = 0; i < s_.sunRays; ++i) {
      const glm::dvec2 u = stratified(i, s_.sunRays, rng);
      const double cosTheta = 1 - u.x * (1 - cosSunRadius_);
      const double sinTheta = std::sqrt(std::max(0.0, 1 - cosTheta * cosTheta));
      const double phi = 2 * kPi * u.y;
      const glm::dvec3 l =
          cosTheta * sun_ + sinTheta * (std::cos(phi) * sunT_ + std::sin(phi) * sunB_);
      const double nDotL = glm::dot(n, l);
      double sHit;
      if (nDotL > 0 && !surface_.intersect(origin, l, start, far, sHit)) sunSum += nDotL;
    }
    const glm::dvec3 direct =
        albedo / kPi * glm::dvec3(s_.lighting.sunIrradiance) * (sunSum / s_.sunRays);

    // Sky: cosine-weighted directions around N.
    glm::dvec3 t, b;
    frameAround(n, t, b);
    glm::dvec3 incoming(0.0);
    for (int i = 0; i < s_.skyRays; ++i) {
      const glm::dvec2 u = stratified(i, s_.skyRays, rng);
      const double r = std::sqrt(u.x), phi = 2 * kPi * u.y;
      const glm::dvec3 d = r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(1 - u.x) * n;
      double sHit;
      if (!surface_.intersect(origin, d, start, far, sHit)) {
        incoming += glm::dvec3(s_.lighting.skyRadiance);
        continue;
      }
      if (s_.interreflection) incoming += bounce(origin + sHit * d);
    }
    const glm::dvec3 ambient = albedo / kPi * (kPi * incoming / double(s_.skyRays));
    return direct + ambient;
  }

 private:
  // Radiance leaving a terrain point towards the shaded one: its albedo
  // times its direct sun (one shadow ray) and its tangent plane's open sky.
  glm::dvec3 bounce(const glm::dvec3& q) const {
    const glm::dvec3 n = surface_.normalAt(q.x, q.y);
    const glm::dvec3 origin = q + n * (1e-3 * surface_.cell());
    double sHit;
    const double nDotL = glm::dot(n, sun_);
    const double sun =
        nDotL > 0 && !surface_.intersect(origin, sun_, 1e-3 * surface_.cell(), 1e12, sHit) ? nDotL
                                                                                           : 0.0;
    const glm::dvec3 irradiance = glm::dvec3(s_.lighting.sunIrradiance) * sun +
                                  kPi * glm::dvec3(s_.lighting.skyRadiance) * (1 + n.z) / 2.0;
    return glm::dvec3(s_.albedo) / kPi * irradiance;
  }

  const TerrainSurface& surface_;
  const ReferenceSettings& s_;
  glm::dvec3 sun_, sunT_, sunB_;
  double cosSunRadius_;
};

}  // namespace

ReferenceImage renderReference(const Heightfield& field, const ReferenceSettings& s,
                               const std::function<void(double)>& progress) {
  if (s.width == 0 || s.height == 0) throw std::invalid_argument("reference: empty image");
  if (s.sunRays < 1 || s.skyRays < 1) throw std::invalid_argument("reference: ray counts < 1");
  const TerrainSurface surface(field);
  const PixelShader shader(surface, s);

  // Primary rays from the GPU's own matrices, through pixel centres.
  const double aspect = double(s.width) / double(s.height);
  const DepthRange range = depthRangeFor(s.camera, field);
  const glm::dmat4 invViewProj =
      glm::inverse(glm::dmat4(projectionMatrix(s.camera, aspect, range) * viewMatrix(s.camera)));
  const glm::dvec3 eye = s.camera.position;

  ReferenceImage image;
  image.width = s.width;
  image.height = s.height;
  image.radiance.assign(size_t(s.width) * s.height, glm::vec3(0.0f));
  image.terrain.assign(size_t(s.width) * s.height, 0);
  std::atomic<uint32_t> rowsDone{0};
  tbb::parallel_for(uint32_t(0), s.height, [&](uint32_t y) {
    for (uint32_t x = 0; x < s.width; ++x) {
      const glm::dvec4 ndc((x + 0.5) / s.width * 2 - 1, (y + 0.5) / s.height * 2 - 1, 1.0, 1.0);
      const glm::dvec4 farPoint = invViewProj * ndc;
      const glm::dvec3 dir = glm::normalize(glm::dvec3(farPoint) / farPoint.w - eye);
      double sHit;
      double sIn, sOut;
      const size_t pixel = size_t(y) * s.width + x;
      if (!surface.clipToBox(eye, dir, sIn, sOut) ||
          !surface.intersect(eye, dir, sIn, sOut, sHit)) {
        if (s.skyBackground) {
          const glm::vec3 up(dir.x, dir.y, std::max(dir.z, 1e-3));
          image.radiance[pixel] = skyRadiance(s.lighting.sky, glm::normalize(up));
        }
        continue;
      }
      std::mt19937 rng(s.seed * 2654435761u + static_cast<uint32_t>(pixel));
      glm::dvec3 radiance = shader.shade(eye + sHit * dir, rng);
      const double transmittance = std::exp(-double(s.lighting.hazeDensityPerM) * sHit);
      radiance =
          radiance * transmittance + glm::dvec3(s.lighting.skyRadiance) * (1 - transmittance);
      image.radiance[pixel] = glm::vec3(radiance);
      image.terrain[pixel] = 1;
    }
    if (progress) progress(double(++rowsDone) / s.height);
  });
  return image;
}

glm::vec3 referenceRadianceAt(const Heightfield& field, const ReferenceSettings& s,
                              const glm::dvec3& point, uint32_t seed) {
  const TerrainSurface surface(field);
  const PixelShader shader(surface, s);
  std::mt19937 rng(seed);
  return glm::vec3(shader.shade(point, rng));
}

double relativeRmse(const std::vector<glm::vec3>& test, const std::vector<glm::vec3>& reference,
                    const std::vector<uint8_t>& mask) {
  if (test.size() != reference.size() || mask.size() != reference.size()) {
    throw std::invalid_argument("relativeRmse: sizes differ");
  }
  double error = 0, norm = 0;
  for (size_t i = 0; i < reference.size(); ++i) {
    if (!mask[i]) continue;
    const glm::dvec3 d = glm::dvec3(test[i]) - glm::dvec3(reference[i]);
    error += glm::dot(d, d);
    norm += glm::dot(glm::dvec3(reference[i]), glm::dvec3(reference[i]));
  }
  return norm > 0 ? std::sqrt(error / norm) : 0.0;
}

std::vector<uint8_t> interiorMask(const std::vector<uint8_t>& terrain, uint32_t width,
                                  uint32_t height) {
  std::vector<uint8_t> interior(terrain.size(), 0);
  for (uint32_t y = 1; y + 1 < height; ++y) {
    for (uint32_t x = 1; x + 1 < width; ++x) {
      const size_t i = size_t(y) * width + x;
      interior[i] = terrain[i] && terrain[i - 1] && terrain[i + 1] && terrain[i - width] &&
                    terrain[i + width];
    }
  }
  return interior;
}

}  // namespace aal
