#include "aperture/terrain/view/camera.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include "aperture/terrain/units.h"

namespace aal {

namespace {

std::pair<float, float> heightRange(const Heightfield& field) {
  const auto [lo, hi] = std::minmax_element(field.z.begin(), field.z.end());
  return {*lo, *hi};
}
}  // namespace

glm::dvec2 demExtentM(const Heightfield& field) {
  return {(field.width - 1) * field.cellSizeXM, (field.height - 1) * field.cellSizeYM};
}

double cameraReachM(const Heightfield& field) {
  return std::max(kMinCameraReachM, kCameraReachDiagonals * glm::length(demExtentM(field)));
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

namespace {

glm::dmat4 viewMatrixD(const Camera& camera) {
  const glm::dvec3 forward = camera.lookAt - camera.position;
  if (glm::length(forward) < 1e-9) {
    throw std::invalid_argument("camera position and look-at point coincide");
  }
  // Looking straight up or down: pick north as the up hint instead of z.
  const glm::dvec3 f = glm::normalize(forward);
  const glm::dvec3 up = std::abs(f.z) > 0.999 ? glm::dvec3(0, 1, 0) : glm::dvec3(0, 0, 1);
  return glm::lookAt(camera.position, camera.lookAt, up);
}

glm::dmat4 projectionMatrixD(const Camera& camera, double aspect, const DepthRange& range) {
  glm::dmat4 p =
      glm::perspectiveRH_ZO(radians(camera.verticalFovDeg), aspect, range.nearM, range.farM);
  p[1][1] *= -1.0;  // Vulkan's clip space y points down
  return p;
}

}  // namespace

glm::mat4 viewMatrix(const Camera& camera) {
  return glm::mat4(viewMatrixD(camera));
}

glm::mat4 projectionMatrix(const Camera& camera, double aspect, const DepthRange& range) {
  return glm::mat4(projectionMatrixD(camera, aspect, range));
}

glm::dmat4 viewProjectionMatrixD(const Camera& camera, double aspect, const DepthRange& range) {
  return projectionMatrixD(camera, aspect, range) * viewMatrixD(camera);
}

Camera defaultCamera(const Heightfield& field, double aspect, double verticalFovDeg,
                     double belowM) {
  const auto [zMin, zMax] = heightRange(field);
  return framingCamera(demExtentM(field), zMin - belowM, zMax, aspect, 135.0, 30.0, verticalFovDeg);
}

Camera framingCamera(glm::dvec2 extentM, double zMin, double zMax, double aspect, double azimuthDeg,
                     double elevationDeg, double verticalFovDeg, double fill) {
  Camera camera;
  camera.verticalFovDeg = verticalFovDeg;
  const double elevation = radians(elevationDeg), azimuth = radians(azimuthDeg);
  // Camera frame: forward f (from the camera towards the DEM), right r, up u.
  const glm::dvec3 f = -glm::dvec3(std::cos(elevation) * std::sin(azimuth),
                                   std::cos(elevation) * std::cos(azimuth), std::sin(elevation));
  const glm::dvec3 r = glm::normalize(glm::cross(f, glm::dvec3(0, 0, 1)));
  const glm::dvec3 u = glm::cross(r, f);
  std::array<glm::dvec3, 8> corners;
  for (int i = 0; i < 8; ++i) {
    corners[i] = {(i & 1 ? 0.5 : -0.5) * extentM.x, (i & 2 ? 0.5 : -0.5) * extentM.y,
                  i & 4 ? zMax : zMin};
  }
  // A corner q lies within `fill` of the image's half-width and half-height
  // iff it is behind none of the four planes through the camera p with
  // normals n = ±r - a f and ±u - b f (a, b: fill times the tangents of the
  // half fields of view), i.e. q.n <= p.n for every n. With p = X r + Y u +
  // Z f the right and left planes give X - a Z >= h_R and -X - a Z >= h_L
  // (h: the largest q.n over the corners), both tight for X = (h_R - h_L) / 2,
  // Z = -(h_R + h_L) / 2a; likewise Y and Z from the top and bottom. The
  // pair that needs the camera farther back (smaller Z) touches the box on
  // both sides; the other pair is then loose, and its coordinate is moved
  // (it does not change the first pair's planes) until the box's extremes
  // along it are symmetric in the image.
  const double b = fill * std::tan(radians(0.5 * verticalFovDeg));
  const double a = b * aspect;
  const auto highest = [&](const glm::dvec3& n) {
    double h = -std::numeric_limits<double>::infinity();
    for (const glm::dvec3& q : corners) h = std::max(h, glm::dot(q, n));
    return h;
  };
  const double hR = highest(r - a * f), hL = highest(-r - a * f);
  const double hT = highest(u - b * f), hB = highest(-u - b * f);
  const double zH = -(hR + hL) / (2.0 * a), zV = -(hT + hB) / (2.0 * b);
  const double z = std::min(zH, zV);
  double x = 0.5 * (hR - hL), y = 0.5 * (hT - hB);
  // Centre the loose axis (axis = r, tangent a, coordinate x; or u, b, y):
  // the sum of the largest and smallest image coordinate decreases as the
  // camera moves along the axis; within the feasible interval [h_+ + t Z,
  // -h_- - t Z] it changes sign (at each end one extreme is at the edge).
  const auto centreAxis = [&](const glm::dvec3& axis, double t, double hPlus, double hMinus,
                              double& coordinate) {
    double lo = hPlus + t * z, hi = -hMinus - t * z;
    for (int i = 0; i < 100 && hi - lo > 1e-9 * (std::abs(lo) + std::abs(hi) + 1.0); ++i) {
      coordinate = 0.5 * (lo + hi);
      const glm::dvec3 p = x * r + y * u + z * f;
      double most = -1e300, least = 1e300;
      for (const glm::dvec3& q : corners) {
        const double s = glm::dot(q - p, axis) / glm::dot(q - p, f);
        most = std::max(most, s);
        least = std::min(least, s);
      }
      (most + least > 0.0 ? lo : hi) = coordinate;
    }
    coordinate = 0.5 * (lo + hi);
  };
  if (zH <= zV) {
    centreAxis(u, b, hT, hB, y);
  } else {
    centreAxis(r, a, hR, hL, x);
  }
  camera.position = x * r + y * u + z * f;
  // Look at the point of the optical axis as deep as the box's centre.
  const glm::dvec3 centre(0.0, 0.0, 0.5 * (zMin + zMax));
  camera.lookAt = camera.position + std::max(glm::dot(centre - camera.position, f), 1.0) * f;
  return camera;
}

}  // namespace aal
