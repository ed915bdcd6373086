#include "camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

namespace aal {

namespace {
constexpr double kDegToRad = std::numbers::pi / 180.0;

std::pair<float, float> heightRange(const Heightfield& field) {
  const auto [lo, hi] = std::minmax_element(field.z.begin(), field.z.end());
  return {*lo, *hi};
}
}  // namespace

glm::dvec2 demExtentM(const Heightfield& field) {
  return {(field.width - 1) * field.cellSizeXM, (field.height - 1) * field.cellSizeYM};
}

DepthRange depthRangeFor(const Camera& camera, const Heightfield& field) {
  const auto [zMin, zMax] = heightRange(field);
  return depthRangeFor(camera, demExtentM(field), zMin, zMax);
}

DepthRange depthRangeFor(const Camera& camera, glm::dvec2 extentM, double zMin, double zMax) {
  // Distance to the farthest corner of the DEM's bounding box, plus margin.
  double farthest = 0;
  for (double sx : {-0.5, 0.5}) {
    for (double sy : {-0.5, 0.5}) {
      for (double z : {zMin, zMax}) {
        farthest = std::max(
            farthest, glm::length(glm::dvec3(sx * extentM.x, sy * extentM.y, z) - camera.position));
      }
    }
  }
  DepthRange range;
  range.farM = 1.1 * farthest + 10.0;
  // Close enough for a camera near the ground, far enough to keep depth
  // precision (24+ bits over far/near <= 1e5).
  range.nearM = std::max(0.1, range.farM * 1e-5);
  return range;
}

glm::mat4 viewMatrix(const Camera& camera) {
  const glm::dvec3 forward = camera.lookAt - camera.position;
  if (glm::length(forward) < 1e-9) {
    throw std::invalid_argument("camera position and look-at point coincide");
  }
  // Looking straight up or down: pick north as the up hint instead of z.
  const glm::dvec3 f = glm::normalize(forward);
  const glm::dvec3 up = std::abs(f.z) > 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  return glm::mat4(glm::lookAt(camera.position, camera.lookAt, up));
}

glm::mat4 projectionMatrix(const Camera& camera, double aspect, const DepthRange& range) {
  glm::dmat4 p =
      glm::perspectiveRH_ZO(camera.verticalFovDeg * kDegToRad, aspect, range.nearM, range.farM);
  p[1][1] *= -1.0;  // Vulkan's clip space y points down
  return glm::mat4(p);
}

Camera defaultCamera(const Heightfield& field, double aspect) {
  const glm::dvec2 extent = demExtentM(field);
  // Plain variables, not structured bindings: the lambda below captures them.
  const std::pair<float, float> heights = heightRange(field);
  const float zMin = heights.first, zMax = heights.second;
  Camera camera;
  camera.verticalFovDeg = 40.0;
  camera.lookAt = {0.0, 0.0, 0.5 * (zMin + zMax)};
  const double elevation = 30.0 * kDegToRad, azimuth = 135.0 * kDegToRad;  // from the south-east
  const glm::dvec3 fromTarget(std::cos(elevation) * std::sin(azimuth),
                              std::cos(elevation) * std::cos(azimuth), std::sin(elevation));
  // The closest distance at which every corner of the DEM's box stays inside
  // 90% of the image (bisection on the distance; the sphere bound is far
  // enough to start from).
  const double radius = 0.5 * std::sqrt(extent.x * extent.x + extent.y * extent.y +
                                        double(zMax - zMin) * (zMax - zMin));
  auto fits = [&](double distance) {
    Camera c = camera;
    c.position = camera.lookAt + distance * fromTarget;
    DepthRange range{distance * 1e-3, distance * 10};
    const glm::mat4 m = projectionMatrix(c, aspect, range) * viewMatrix(c);
    for (double sx : {-0.5, 0.5}) {
      for (double sy : {-0.5, 0.5}) {
        for (double z : {double(zMin), double(zMax)}) {
          const glm::vec4 p =
              m * glm::vec4(float(sx * extent.x), float(sy * extent.y), float(z), 1);
          if (p.w <= 0 || std::abs(p.x / p.w) > 0.9f || std::abs(p.y / p.w) > 0.9f) return false;
        }
      }
    }
    return true;
  };
  double lo = 0.1 * radius, hi = 10.0 * radius + 1.0;
  for (int i = 0; i < 60; ++i) {
    const double mid = 0.5 * (lo + hi);
    (fits(mid) ? hi : lo) = mid;
  }
  camera.position = camera.lookAt + hi * fromTarget;
  return camera;
}

}  // namespace aal
