// The default camera (terrain/view/camera.h, framingCamera): the DEM's bounding
// box fitted to the view frustum from the default viewing direction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

#include "aperture/terrain/view/camera.h"

namespace aal {
namespace {

struct Bounds {
  double xMin = 1e9, xMax = -1e9, yMin = 1e9, yMax = -1e9;
};

// Normalised device coordinates of the box's eight corners.
Bounds projectedBox(const Camera& camera, glm::dvec2 extent, double zMin, double zMax,
                    double aspect) {
  const DepthRange range = depthRangeFor(camera, extent, zMin, zMax);
  const glm::mat4 m = projectionMatrix(camera, aspect, range) * viewMatrix(camera);
  Bounds b;
  for (double sx : {-0.5, 0.5}) {
    for (double sy : {-0.5, 0.5}) {
      for (double z : {zMin, zMax}) {
        const glm::vec4 p = m * glm::vec4(float(sx * extent.x), float(sy * extent.y), float(z), 1);
        EXPECT_GT(p.w, 0.0f);
        b.xMin = std::min(b.xMin, double(p.x / p.w));
        b.xMax = std::max(b.xMax, double(p.x / p.w));
        b.yMin = std::min(b.yMin, double(p.y / p.w));
        b.yMax = std::max(b.yMax, double(p.y / p.w));
      }
    }
  }
  return b;
}

// The default view once showed jacksboro small in a void (the old
// camera looked at the box's centre, so the near corner bound the view and
// the far half of the image stayed empty). Now every corner lies within 90%
// of the half-image, the tighter axis is touched on both sides and the other
// is centred: for several box shapes, heights, aspects and directions.
TEST(FramingCamera, FitsTheBoxToTheFrustumTouchingOneAxisAndCentringTheOther) {
  struct Case {
    glm::dvec2 extent;
    double zMin, zMax, aspect, azimuth, elevation;
  };
  for (const Case& c : {Case{{30150, 25725}, 226, 944, 16.0 / 9.0, 135, 30},  // jacksboro
                        Case{{30150, 25725}, 226, 944, 1.0, 135, 30},
                        Case{{30150, 25725}, 226, 944, 9.0 / 16.0, 135, 30},
                        Case{{1000, 8000}, 0, 3000, 16.0 / 9.0, 200, 55},
                        Case{{5000, 500}, -100, 100, 2.0, 10, 10}}) {
    const Camera cam = framingCamera(c.extent, c.zMin, c.zMax, c.aspect, c.azimuth, c.elevation);
    const Bounds b = projectedBox(cam, c.extent, c.zMin, c.zMax, c.aspect);
    const double tol = 2e-5;
    EXPECT_GE(b.xMin, -0.9 - tol);
    EXPECT_LE(b.xMax, 0.9 + tol);
    EXPECT_GE(b.yMin, -0.9 - tol);
    EXPECT_LE(b.yMax, 0.9 + tol);
    const bool xTouches = b.xMax > 0.9 - tol && b.xMin < -0.9 + tol;
    const bool yTouches = b.yMax > 0.9 - tol && b.yMin < -0.9 + tol;
    EXPECT_TRUE(xTouches || yTouches) << b.xMin << " " << b.xMax << " " << b.yMin << " " << b.yMax;
    EXPECT_NEAR(b.xMin + b.xMax, 0.0, 2 * tol);
    EXPECT_NEAR(b.yMin + b.yMax, 0.0, 2 * tol);
    // Looking along the requested direction.
    const double el = c.elevation * std::numbers::pi / 180, az = c.azimuth * std::numbers::pi / 180;
    const glm::dvec3 expected =
        -glm::dvec3(std::cos(el) * std::sin(az), std::cos(el) * std::cos(az), std::sin(el));
    EXPECT_NEAR(glm::dot(glm::normalize(cam.lookAt - cam.position), expected), 1.0, 1e-9);
    EXPECT_EQ(cam.verticalFovDeg, 40.0);
  }
}

// The default camera is that framing from the south-east, 30° up.
TEST(FramingCamera, DefaultCameraFramesTheDemsBox) {
  Heightfield f;
  f.width = 64;
  f.height = 40;
  f.cellSizeXM = f.cellSizeYM = 30.0;
  f.z.assign(size_t(f.width) * f.height, 100.0f);
  f.z[5] = 400.0f;
  const Camera a = defaultCamera(f, 1.5);
  const Camera b = framingCamera(demExtentM(f), 100.0, 400.0, 1.5);
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.lookAt, b.lookAt);
  EXPECT_GT(a.position.z, 400.0);
  const Bounds bounds = projectedBox(a, demExtentM(f), 100.0, 400.0, 1.5);
  EXPECT_GT(std::max(bounds.xMax - bounds.xMin, bounds.yMax - bounds.yMin), 1.8 - 1e-4);
}

}  // namespace
}  // namespace aal
