// The viewer's camera as pure math (no window): fly mode like a game engine's
// editor camera or Blender's fly mode, and orbit mode around a point. Speeds
// scale with the height above the ground, the camera never goes below the
// terrain, and frame() shows the whole DEM. World frame of docs/design.md §1
// (x east, y north, z up, metres, origin at the DEM centre).
#pragma once

#include <memory>
#include <optional>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/view/camera.h"

namespace aal {

enum class CameraMode {
  Fly,    // look around from the camera; move along the view
  Orbit,  // turn around a pivot point; move the pivot
};

// One frame's input, already mapped from keys and mouse.
struct CameraInput {
  // Fly: x right (D - A), y forward along the view (W - S), z world up
  // (E - Q); each in [-1, 1]. Orbit: x, y move the pivot over the ground
  // (relative to the view), z up/down.
  glm::dvec3 move{0.0};
  // Mouse movement while looking (right button held), pixels; x right, y down.
  glm::dvec2 lookPixels{0.0};
  // Mouse wheel steps (up positive): fly changes the speed, orbit zooms.
  double wheelSteps = 0;
  bool fast = false;  // Shift
  double dtSeconds = 0;
};

struct CameraControllerOptions {
  double lookRadPerPixel = 0.003;
  // Fly speed in metres per second per metre of height above the ground (at
  // speed factor 1): 100 m up moves 25 m/s, 1 km up 250 m/s.
  double speedPerHeight = 0.25;
  // The height used for the speed never drops below this, so that the
  // camera still moves when it sits on the ground.
  double minSpeedHeightM = 5;
  double wheelStep = 1.25;  // speed (fly) or distance (orbit) factor per wheel step
  double fastFactor = 4;    // Shift
  double verticalFovDeg = 40;
};

class CameraController {
 public:
  // Shares ownership of the DEM that the camera collides with. Starts framed
  // (frame(aspect)) in fly mode.
  CameraController(std::shared_ptr<const Heightfield> field, double aspect,
                   const CameraControllerOptions& options = {});

  // Moves and turns the camera by one frame of input, then keeps it above
  // the ground.
  void update(const CameraInput& input);
  // Frames the whole DEM (aal-render's default view) and resets the speed
  // factor; orbit mode orbits the DEM's centre.
  void frame(double aspect);
  // Places the camera (e.g. from a camera path), then keeps it above the ground.
  void setCamera(const Camera& camera);
  // Orbit: the pivot becomes the terrain point under the view centre (or a
  // point ahead when the view misses the terrain). Fly: keeps the view.
  void setMode(CameraMode mode);

  CameraMode mode() const { return mode_; }
  Camera camera() const;
  glm::dvec3 position() const { return position_; }
  // Unit view direction.
  glm::dvec3 forward() const;
  glm::dvec3 pivot() const { return pivot_; }
  // Fly speed without Shift, metres per second, at the current height.
  double speedMps() const;
  // Multiplies speedPerHeight; changed by the mouse wheel in fly mode.
  double speedFactor() const { return speedFactor_; }

  // The terrain height (bilinear over the DEM; beyond its edge the nearest
  // edge texel's) at world (x, y).
  double groundHeightAt(double x, double y) const;
  double heightAboveGround() const;
  // Smallest allowed height above the ground: 2 m or 1.5 cells, whichever is
  // larger (the renderer's grid is coarser than the DEM on large ones).
  double minClearanceM() const;
  // First point where the ray from `origin` along unit `direction` meets the
  // terrain within `maxDistanceM`, marching a quarter cell at a time.
  std::optional<glm::dvec3> raycast(const glm::dvec3& origin, const glm::dvec3& direction,
                                    double maxDistanceM) const;

 private:
  void lookAt(const glm::dvec3& from, const glm::dvec3& target);
  void placeOrbitCamera();
  void keepAboveGround();

  std::shared_ptr<const Heightfield> field_;
  CameraControllerOptions options_;
  CameraMode mode_ = CameraMode::Fly;
  glm::dvec3 position_{0.0};
  double yawRad_ = 0;    // view azimuth, counter-clockwise from +x (east)
  double pitchRad_ = 0;  // view elevation above the horizontal
  double speedFactor_ = 1;
  glm::dvec3 pivot_{0.0};  // orbit centre
  double orbitDistanceM_ = 1000;
};

}  // namespace aal
