#include "aperture/terrain/view/camera_controller.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/geometric.hpp>

namespace aal {

namespace {
constexpr double kMaxPitchRad = 1.5533;  // 89 degrees: the view never flips over the pole
constexpr double kMinSpeedFactor = 1e-3, kMaxSpeedFactor = 1e3;
}  // namespace

CameraController::CameraController(std::shared_ptr<const Heightfield> field, double aspect,
                                   const CameraControllerOptions& options)
    : field_(std::move(field)), options_(options) {
  if (!field_ || field_->width < 1 || field_->height < 1 || field_->z.empty()) {
    throw std::invalid_argument("camera controller: empty heightfield");
  }
  frame(aspect);
}

double CameraController::groundHeightAt(double x, double y) const {
  const Heightfield& f = *field_;
  // World to fractional texel coordinates: column 0 west, row 0 north.
  return f.bilinearHeight(x / f.cellSizeXM + 0.5 * (f.width - 1),
                          0.5 * (f.height - 1) - y / f.cellSizeYM);
}

double CameraController::minClearanceM() const {
  return std::max(2.0, 1.5 * std::max(field_->cellSizeXM, field_->cellSizeYM));
}

double CameraController::heightAboveGround() const {
  return position_.z - groundHeightAt(position_.x, position_.y);
}

double CameraController::speedMps() const {
  const double height = std::max(heightAboveGround(), options_.minSpeedHeightM);
  return options_.speedPerHeight * speedFactor_ * height;
}

glm::dvec3 CameraController::forward() const {
  return {std::cos(pitchRad_) * std::cos(yawRad_), std::cos(pitchRad_) * std::sin(yawRad_),
          std::sin(pitchRad_)};
}

Camera CameraController::camera() const {
  Camera c;
  c.position = position_;
  // Only the direction matters to the view matrix; the distance keeps the
  // look-at point well away from the position in floats.
  c.lookAt = mode_ == CameraMode::Orbit ? pivot_ : position_ + 1000.0 * forward();
  c.verticalFovDeg = options_.verticalFovDeg;
  return c;
}

void CameraController::lookAt(const glm::dvec3& from, const glm::dvec3& target) {
  position_ = from;
  const glm::dvec3 d = target - from;
  const double horizontal = std::hypot(d.x, d.y);
  if (horizontal < 1e-9 && std::abs(d.z) < 1e-9) return;
  yawRad_ = horizontal > 1e-9 ? std::atan2(d.y, d.x) : yawRad_;
  pitchRad_ = std::clamp(std::atan2(d.z, horizontal), -kMaxPitchRad, kMaxPitchRad);
}

void CameraController::frame(double aspect) {
  Camera c = defaultCamera(*field_, aspect);
  options_.verticalFovDeg = c.verticalFovDeg;
  speedFactor_ = 1;
  pivot_ = c.lookAt;
  orbitDistanceM_ = glm::length(c.position - c.lookAt);
  lookAt(c.position, c.lookAt);
  keepAboveGround();
}

void CameraController::setCamera(const Camera& camera) {
  options_.verticalFovDeg = camera.verticalFovDeg;
  lookAt(camera.position, camera.lookAt);
  if (mode_ == CameraMode::Orbit) {
    pivot_ = camera.lookAt;
    orbitDistanceM_ = std::max(glm::length(camera.position - camera.lookAt), 1.0);
  }
  keepAboveGround();
}

std::optional<glm::dvec3> CameraController::raycast(const glm::dvec3& origin,
                                                    const glm::dvec3& direction,
                                                    double maxDistanceM) const {
  const double step = 0.25 * std::min(field_->cellSizeXM, field_->cellSizeYM);
  // Bounded so that a huge DEM seen from far costs at most ~1e5 samples.
  const double stride = std::max(step, maxDistanceM / 1e5);
  double previous = 0;
  for (double t = 0; t <= maxDistanceM; t += stride) {
    const glm::dvec3 p = origin + t * direction;
    if (p.z <= groundHeightAt(p.x, p.y)) {
      // Refine between the last point above and this one by bisection.
      double lo = previous, hi = t;
      for (int i = 0; i < 30; ++i) {
        const double mid = 0.5 * (lo + hi);
        const glm::dvec3 q = origin + mid * direction;
        (q.z <= groundHeightAt(q.x, q.y) ? hi : lo) = mid;
      }
      return origin + hi * direction;
    }
    previous = t;
  }
  return std::nullopt;
}

void CameraController::setMode(CameraMode mode) {
  if (mode == mode_) return;
  if (mode == CameraMode::Orbit) {
    const glm::dvec2 extent = demExtentM(*field_);
    const double reach = 2.0 * std::hypot(extent.x, extent.y) + heightAboveGround();
    const std::optional<glm::dvec3> hit = raycast(position_, forward(), reach);
    const double ahead = std::max(heightAboveGround(), 10.0 * minClearanceM());
    pivot_ = hit ? *hit : position_ + ahead * forward();
    orbitDistanceM_ = std::max(glm::length(position_ - pivot_), 1.0);
  }
  mode_ = mode;
}

void CameraController::placeOrbitCamera() {
  // The camera sits on a sphere around the pivot, opposite the view direction.
  position_ = pivot_ - orbitDistanceM_ * forward();
}

void CameraController::keepAboveGround() {
  const double floor = groundHeightAt(position_.x, position_.y) + minClearanceM();
  if (position_.z >= floor) return;
  position_.z = floor;
  // Orbit: keep looking at the pivot from the raised position.
  if (mode_ == CameraMode::Orbit) {
    lookAt(position_, pivot_);
    orbitDistanceM_ = std::max(glm::length(position_ - pivot_), 1.0);
  }
}

void CameraController::update(const CameraInput& in) {
  yawRad_ -= in.lookPixels.x * options_.lookRadPerPixel;
  pitchRad_ = std::clamp(pitchRad_ - in.lookPixels.y * options_.lookRadPerPixel, -kMaxPitchRad,
                         kMaxPitchRad);
  const double boost = in.fast ? options_.fastFactor : 1.0;
  const glm::dvec3 f = forward();
  const glm::dvec3 right = glm::normalize(glm::dvec3(std::sin(yawRad_), -std::cos(yawRad_), 0));

  if (mode_ == CameraMode::Fly) {
    speedFactor_ = std::clamp(speedFactor_ * std::pow(options_.wheelStep, in.wheelSteps),
                              kMinSpeedFactor, kMaxSpeedFactor);
    const double distance = speedMps() * boost * in.dtSeconds;
    position_ += distance * (in.move.x * right + in.move.y * f + in.move.z * glm::dvec3(0, 0, 1));
  } else {
    orbitDistanceM_ =
        std::clamp(orbitDistanceM_ / std::pow(options_.wheelStep, in.wheelSteps), 1.0, 1e8);
    // The pivot moves over the ground at a speed set by the orbit distance.
    const glm::dvec3 ahead(std::cos(yawRad_), std::sin(yawRad_), 0.0);
    const double distance =
        options_.speedPerHeight * speedFactor_ * orbitDistanceM_ * boost * in.dtSeconds;
    pivot_ += distance * (in.move.x * right + in.move.y * ahead + in.move.z * glm::dvec3(0, 0, 1));
    placeOrbitCamera();
  }
  keepAboveGround();
}

}  // namespace aal
