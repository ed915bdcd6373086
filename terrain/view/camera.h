// A pinhole camera in the DEM's world frame (x east, y north, z up, metres,
// origin at the DEM centre; docs/design.md §1) and its Vulkan matrices.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "aperture/terrain/heightfield.h"

namespace aal {

struct Camera {
  glm::dvec3 position{0, 0, 1000};
  glm::dvec3 lookAt{0, 0, 0};
  double verticalFovDeg = 45.0;
};

// The vertical field of view the tools take, in degrees: --fov and every
// keyframe of a camera path (below 1 degree the view is a flat patch of one
// colour, towards 180 the projection diverges).
constexpr double kMinFovDeg = 1.0, kMaxFovDeg = 170.0;

// How far from the DEM's centre a camera, or the point it looks at, may be:
// 10,000 km, or kCameraReachDiagonals of the DEM's diagonal for a DEM wider
// than 100 km. Beyond that the terrain is far below a pixel and the single
// precision of the device's matrices breaks the projection (a camera 1e300 m
// away drew flat grey and exited 0).
constexpr double kMinCameraReachM = 1e7;
constexpr double kCameraReachDiagonals = 100.0;
double cameraReachM(const Heightfield& field);

// Near and far planes that keep the whole DEM in view from `camera`.
struct DepthRange {
  double nearM = 1, farM = 1e5;
};
DepthRange depthRangeFor(const Camera& camera, const Heightfield& field);
// The same for a DEM box: extent in metres (x, y) and height range.
DepthRange depthRangeFor(const Camera& camera, glm::dvec2 extentM, double zMin, double zMax);

// View and projection for Vulkan: right-handed world, clip y pointing down,
// depth 0 (near) .. 1 (far). Throws std::invalid_argument when position and
// lookAt coincide.
glm::mat4 viewMatrix(const Camera& camera);
glm::mat4 projectionMatrix(const Camera& camera, double aspect, const DepthRange& range);
// Projection times view in double: what a reprojection from one frame's
// depth to another's inverts. With a near plane 1e-5 of the far one the
// projection's depth and w rows are nearly parallel, and the inverse of its
// float copy misplaces points by pixels.
glm::dmat4 viewProjectionMatrixD(const Camera& camera, double aspect, const DepthRange& range);

// The camera the tools start with: framingCamera of the DEM's bounding box
// from the south-east, 30 degrees above the horizon, for that field of view.
// `belowM`: a solid base that deep under the lowest point is framed too.
Camera defaultCamera(const Heightfield& field, double aspect, double verticalFovDeg = 40.0,
                     double belowM = 0.0);

// The camera looking from (azimuthDeg clockwise from north, elevationDeg
// above the horizon) that frames the box of a DEM (extent in metres, centred
// on the origin; heights zMin..zMax) as tightly as the view frustum allows:
// every corner inside `fill` of the image's half-width and half-height, the
// tighter of the two touched by a corner on both sides and the other
// centred (closed form: docs/rendering.md, "Default camera").
Camera framingCamera(glm::dvec2 extentM, double zMin, double zMax, double aspect,
                     double azimuthDeg = 135.0, double elevationDeg = 30.0,
                     double verticalFovDeg = 40.0, double fill = 0.9);

// DEM extent in metres (x: west to east, y: south to north).
glm::dvec2 demExtentM(const Heightfield& field);

}  // namespace aal
