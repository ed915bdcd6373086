#include "aperture/terrain/reference/reference_renderer.h"

#include "aperture/terrain/reference/terrain_surface.h"
#include "aperture/terrain/units.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/matrix.hpp>
#include <glm/vec4.hpp>

namespace aal {

namespace {

// An orthonormal frame around n (Duff et al. 2017, "Building an Orthonormal
// Basis, Revisited").
void frameAround(const glm::dvec3& n, glm::dvec3& t, glm::dvec3& b) {
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const double c = n.x * n.y * a;
  t = {1 + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

// Jittered samples on a rows x columns grid of the unit square with exactly
// n cells (rows the largest divisor of n not above its square root: k x k
// for square n, 8 x 16 for 128, 1 x n for a prime), one sample per cell.
// Every cell has the same area, so the mean is unbiased for any n. (A k x k
// grid with k = ceil(sqrt(n)) and its first n cells leaves the last cells
// empty: with 128 rays the sky's azimuths 330-360 degrees around N and part
// of 300-330 were never sampled, docs/comparison.md.)
template <class Rng>
glm::dvec2 stratified(int i, int n, Rng& rng) {
  int rows = static_cast<int>(std::sqrt(double(n)));
  while (n % rows != 0) --rows;
  const int columns = n / rows;
  std::uniform_real_distribution<double> u(0.0, 1.0);
  return {((i % columns) + u(rng)) / columns, ((i / columns) + u(rng)) / rows};
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
  if (s.subpixels < 1 || s.subpixels > kMaxReferenceSubpixels) {
    throw std::invalid_argument("reference: subpixels per axis must be 1.." +
                                std::to_string(kMaxReferenceSubpixels));
  }
  const TerrainSurface surface(field);

  // Primary rays from the GPU's own matrices, through subpixel centres.
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
  // Each pixel's subpixels share its ray budget (docs/comparison.md, the
  // pixel's footprint).
  const int n = s.subpixels;
  const int subpixelCount = n * n;
  ReferenceSettings shared = s;
  shared.sunRays = (s.sunRays + subpixelCount - 1) / subpixelCount;
  shared.skyRays = (s.skyRays + subpixelCount - 1) / subpixelCount;
  const PixelShader subpixelShader(surface, shared);
  tbb::parallel_for(uint32_t(0), s.height, [&](uint32_t y) {
    for (uint32_t x = 0; x < s.width; ++x) {
      const size_t pixel = size_t(y) * s.width + x;
      // One generator per pixel for all its subpixels (seeded as before
      // subpixels, so one subpixel gives the same image).
      std::mt19937 rng(s.seed * 2654435761u + static_cast<uint32_t>(pixel));
      glm::dvec3 sum(0.0);
      bool allTerrain = true;
      for (int j = 0; j < subpixelCount; ++j) {
        // Subpixel centres of a regular n x n grid (the pixel's centre for n = 1).
        const double sx = x + (j % n + 0.5) / n, sy = y + (j / n + 0.5) / n;
        const glm::dvec4 ndc(sx / s.width * 2 - 1, sy / s.height * 2 - 1, 1.0, 1.0);
        const glm::dvec4 farPoint = invViewProj * ndc;
        const glm::dvec3 dir = glm::normalize(glm::dvec3(farPoint) / farPoint.w - eye);
        double sHit;
        double sIn, sOut;
        if (!surface.clipToBox(eye, dir, sIn, sOut) ||
            !surface.intersect(eye, dir, sIn, sOut, sHit)) {
          allTerrain = false;
          if (s.skyBackground) {
            const glm::vec3 up(dir.x, dir.y, std::max(dir.z, 1e-3));
            sum += glm::dvec3(skyRadiance(s.lighting.sky, glm::normalize(up)));
          }
          continue;
        }
        glm::dvec3 radiance = subpixelShader.shade(eye + sHit * dir, rng);
        const double transmittance = std::exp(-double(s.lighting.hazeDensityPerM) * sHit);
        sum += radiance * transmittance + glm::dvec3(s.lighting.skyRadiance) * (1 - transmittance);
      }
      image.radiance[pixel] = glm::vec3(sum / double(subpixelCount));
      image.terrain[pixel] = allTerrain ? 1 : 0;
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
