// The viewer's camera as pure math (terrain/view/camera_controller.h): ground
// collision, speed scaling, framing, orbit mode. No window.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include <glm/geometric.hpp>

#include "aperture/terrain/view/camera_controller.h"

namespace aal {
namespace {

// A w x h DEM with 10 m cells whose heights are given by `height(x, y)` in
// world metres (x east, y north, origin at the centre).
template <typename F>
std::shared_ptr<const Heightfield> makeField(int w, int h, F height) {
  auto field = std::make_shared<Heightfield>();
  field->width = w;
  field->height = h;
  field->cellSizeXM = field->cellSizeYM = 10.0;
  field->z.resize(size_t(w) * h);
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const double x = (col - 0.5 * (w - 1)) * 10.0, y = (0.5 * (h - 1) - row) * 10.0;
      field->z[field->index(col, row)] = static_cast<float>(height(x, y));
    }
  }
  return field;
}

std::shared_ptr<const Heightfield> flatField(double z) {
  return makeField(65, 65, [z](double, double) { return z; });
}

CameraInput forwardFor(double seconds) {
  CameraInput in;
  in.move = {0, 1, 0};
  in.dtSeconds = seconds;
  return in;
}

Camera lookingFrom(glm::dvec3 position, glm::dvec3 lookAt) {
  Camera c;
  c.position = position;
  c.lookAt = lookAt;
  return c;
}

TEST(CameraController, GroundHeightIsBilinearInTheWorldFrame) {
  // z = x + 2y is reproduced exactly by bilinear interpolation.
  CameraController c(makeField(33, 17, [](double x, double y) { return x + 2 * y; }), 1.5);
  EXPECT_NEAR(c.groundHeightAt(0, 0), 0, 1e-6);
  EXPECT_NEAR(c.groundHeightAt(33.3, -21.7), 33.3 - 43.4, 1e-4);
  // Beyond the edge: the edge's height (x is clamped to +160 m).
  EXPECT_NEAR(c.groundHeightAt(500, 0), 160, 1e-4);
}

TEST(CameraController, FlyingDownIntoTheGroundStopsAboveIt) {
  CameraController c(flatField(100), 1.5);
  c.setCamera(lookingFrom({0, 0, 150}, {0, 0, 0}));  // straight down
  for (int i = 0; i < 100; ++i) c.update(forwardFor(0.1));
  EXPECT_NEAR(c.position().z, 100 + c.minClearanceM(), 1e-9);
  EXPECT_GE(c.heightAboveGround(), c.minClearanceM() - 1e-9);
}

TEST(CameraController, PlacingTheCameraUnderTheGroundLiftsIt) {
  CameraController c(makeField(65, 65, [](double x, double) { return 0.5 * x; }), 1.5);
  c.setCamera(lookingFrom({100, 0, -500}, {200, 0, -500}));
  EXPECT_NEAR(c.position().z, 50 + c.minClearanceM(), 1e-6);
  // The view direction is kept.
  EXPECT_NEAR(c.forward().x, 1, 1e-9);
}

TEST(CameraController, DescendingKeyStopsAtTheClearance) {
  CameraController c(flatField(0), 1.5);
  c.setCamera(lookingFrom({0, 0, 50}, {100, 0, 50}));
  CameraInput down;
  down.move = {0, 0, -1};
  down.dtSeconds = 1;
  for (int i = 0; i < 50; ++i) c.update(down);
  EXPECT_NEAR(c.position().z, c.minClearanceM(), 1e-9);
  EXPECT_EQ(c.minClearanceM(), 15.0);  // 1.5 cells of 10 m
}

TEST(CameraController, SpeedScalesWithHeightAboveGround) {
  CameraController c(flatField(200), 1.5);
  c.setCamera(lookingFrom({0, 0, 300}, {100, 0, 300}));
  const double low = c.speedMps();
  c.setCamera(lookingFrom({0, 0, 1200}, {100, 0, 1200}));
  const double high = c.speedMps();
  EXPECT_NEAR(high / low, 10.0, 1e-9);  // 1000 m vs 100 m above the ground
  EXPECT_NEAR(low, 0.25 * 100, 1e-9);   // speedPerHeight at factor 1
  // One second forward at that speed, level flight.
  const glm::dvec3 before = c.position();
  c.update(forwardFor(1.0));
  EXPECT_NEAR(glm::length(c.position() - before), high, 1e-6);
}

TEST(CameraController, ShiftAndTheWheelChangeTheSpeed) {
  CameraController c(flatField(0), 1.5);
  c.setCamera(lookingFrom({0, 0, 400}, {100, 0, 400}));
  const double base = c.speedMps();
  CameraInput wheel;
  wheel.wheelSteps = 2;
  c.update(wheel);
  EXPECT_NEAR(c.speedMps() / base, 1.25 * 1.25, 1e-9);
  EXPECT_NEAR(c.speedFactor(), 1.5625, 1e-12);

  CameraInput fast = forwardFor(0.5);
  fast.fast = true;
  const glm::dvec3 before = c.position();
  const double speed = c.speedMps();
  c.update(fast);
  EXPECT_NEAR(glm::length(c.position() - before), 4 * speed * 0.5, 1e-6);
}

TEST(CameraController, SpeedNeverDropsToZeroOnTheGround) {
  CameraController c(flatField(0), 1.5);
  c.setCamera(lookingFrom({0, 0, 0}, {100, 0, 0}));
  EXPECT_GT(c.speedMps(), 0.0);
}

TEST(CameraController, LookingTurnsAndNeverFlipsOverThePole) {
  CameraController c(flatField(0), 1.5);
  c.setCamera(lookingFrom({0, 0, 500}, {100, 0, 500}));  // east
  CameraInput look;
  look.lookPixels = {0, -1e6};  // mouse far up
  c.update(look);
  EXPECT_GT(c.forward().z, 0.99);
  EXPECT_LT(c.forward().z, 1.0);                        // clamped below straight up
  look.lookPixels = {-std::acos(-1.0) / 2 / 0.003, 0};  // a quarter turn left
  c.setCamera(lookingFrom({0, 0, 500}, {100, 0, 500}));
  c.update(look);
  EXPECT_NEAR(c.forward().y, 1.0, 1e-6);  // now north
}

TEST(CameraController, FrameShowsTheWholeDem) {
  auto field = makeField(201, 101, [](double x, double y) { return 0.1 * x + 0.05 * y + 300; });
  const double aspect = 16.0 / 9.0;
  CameraController c(field, aspect);
  c.setCamera(lookingFrom({5000, 5000, 50}, {6000, 5000, 50}));  // somewhere else
  c.frame(aspect);
  const Camera cam = c.camera();
  const glm::mat4 m = projectionMatrix(cam, aspect, depthRangeFor(cam, *field)) * viewMatrix(cam);
  const glm::dvec2 extent = demExtentM(*field);
  for (double sx : {-0.5, 0.5}) {
    for (double sy : {-0.5, 0.5}) {
      const double z = c.groundHeightAt(sx * extent.x, sy * extent.y);
      const glm::vec4 p = m * glm::vec4(float(sx * extent.x), float(sy * extent.y), float(z), 1);
      ASSERT_GT(p.w, 0);
      EXPECT_LE(std::abs(p.x / p.w), 1.0f);
      EXPECT_LE(std::abs(p.y / p.w), 1.0f);
    }
  }
  // The DEM's centre is in the middle half of the view (the framing centres
  // the box's picture, whose near half is the larger: docs/rendering.md,
  // "Default camera"), and the camera sits above the ground.
  const glm::vec4 centre = m * glm::vec4(0, 0, 300, 1);
  EXPECT_LT(std::abs(centre.x / centre.w), 0.5f);
  EXPECT_LT(std::abs(centre.y / centre.w), 0.5f);
  EXPECT_GT(c.heightAboveGround(), 0);
  EXPECT_EQ(c.speedFactor(), 1.0);
}

TEST(CameraController, OrbitTurnsAroundTheTerrainPointInView) {
  CameraController c(flatField(0), 1.5);
  c.setCamera(lookingFrom({-300, 0, 300}, {0, 0, 0}));  // 45 degrees down at the centre
  c.setMode(CameraMode::Orbit);
  EXPECT_NEAR(glm::length(c.pivot() - glm::dvec3(0, 0, 0)), 0, 0.05);
  const double distance = glm::length(c.position() - c.pivot());
  CameraInput turn;
  turn.lookPixels = {200, 0};
  c.update(turn);
  EXPECT_NEAR(glm::length(c.position() - c.pivot()), distance, 1e-6);
  EXPECT_GT(std::abs(c.position().y), 10.0);  // moved round the pivot
  EXPECT_NEAR(glm::length(c.camera().lookAt - c.pivot()), 0, 1e-9);
  // The wheel zooms in.
  CameraInput zoom;
  zoom.wheelSteps = 1;
  c.update(zoom);
  EXPECT_NEAR(glm::length(c.position() - c.pivot()), distance / 1.25, 1e-6);
}

TEST(CameraController, OrbitCameraStaysAboveTheGround) {
  CameraController c(flatField(0), 1.5);
  c.setCamera(lookingFrom({-300, 0, 300}, {0, 0, 0}));
  c.setMode(CameraMode::Orbit);
  CameraInput under;
  under.lookPixels = {0, 1e6};  // swing the camera below the pivot
  c.update(under);
  EXPECT_GE(c.heightAboveGround(), c.minClearanceM() - 1e-9);
}

TEST(CameraController, RaycastFindsTheGround) {
  CameraController c(flatField(50), 1.5);
  const auto hit = c.raycast({0, 0, 1050}, glm::normalize(glm::dvec3(1, 0, -1)), 5000);
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->z, 50, 0.01);
  EXPECT_NEAR(hit->x, 1000, 0.01);
  EXPECT_FALSE(c.raycast({0, 0, 1050}, {0, 0, 1}, 5000).has_value());
}

}  // namespace
}  // namespace aal
