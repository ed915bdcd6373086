// A pinhole camera in the DEM's world frame (x east, y north, z up, metres,
// origin at the DEM centre; docs/design.md §1) and its Vulkan matrices.
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "heightfield.h"

namespace aal {

struct Camera {
  glm::dvec3 position{0, 0, 1000};
  glm::dvec3 lookAt{0, 0, 0};
  double verticalFovDeg = 45.0;
};

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

// The camera the tools start with: from the south-east, 30 degrees above the
// horizon, far enough that the whole DEM fits the vertical field of view.
Camera defaultCamera(const Heightfield& field, double aspect);

// DEM extent in metres (x: west to east, y: south to north).
glm::dvec2 demExtentM(const Heightfield& field);

}  // namespace aal
