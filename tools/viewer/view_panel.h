// The viewer's Dear ImGui panel: sun and sky, shading mode, obscurance,
// camera and display settings, loading progress, messages and timings. It
// edits the settings it is given and reports the buttons pressed.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/view/camera_controller.h"
#include "aperture/tools/viewer/view_lighting.h"

namespace aal {

// What the panel edits (by reference) and shows.
struct ViewPanelModel {
  ViewLighting& lighting;
  ShadingMode& mode;
  int& anisotropy;  // FrameSettings::anisotropy
  ObscuranceSettings& obscurance;
  bool& vsync;
  // Frames drawn smaller are rebuilt at full resolution (FrameOutput::temporal)
  // rather than scaled up: aal-view --temporal, resolved.
  bool& temporal;
  CameraMode cameraMode = CameraMode::Fly;
  std::string demName;
  int demWidth = 0, demHeight = 0;
  size_t triangles = 0;
  std::optional<double> bakeProgress;  // set while the aperture map is baked
  std::string message;                 // last message (load errors, screenshots)
  // Why the horizon mode is not offered (shown disabled with it); empty:
  // the scene has directional horizons.
  std::string horizonsMissing;
  double framesPerSecond = 0, frameMs = 0;
  std::vector<std::pair<std::string, double>> passMs;  // GPU time per pass
  float resolutionScale = 1;                           // of the last frame (dynamic resolution)
  double targetFps = 0;  // edited: the dynamic resolution's target (0: off)
  double speedMps = 0, heightAboveGroundM = 0;
  // Obscurance radius R: the DEM's default (used when radiusM is 0) and the
  // largest allowed (the shorter side of the DEM).
  float defaultObscuranceRadiusM = 0, maxObscuranceRadiusM = 1;
};

struct ViewPanelActions {
  bool screenshot = false;
  bool frameDem = false;
  bool toggleOrbit = false;
  bool vsyncChanged = false;
  bool temporalChanged = false;
};

ViewPanelActions drawViewPanel(ViewPanelModel& model);

}  // namespace aal
