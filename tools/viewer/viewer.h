// aal-view's application: a window on the shared engine. Each frame is a
// short list of steps: input -> camera -> loading -> UI -> terrain passes
// (TerrainRenderer::record) -> blit to the swapchain image -> UI render pass
// -> present. See docs/viewer.md.
#pragma once

#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/frame_sync.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/engine/window/swapchain.h"
#include "aperture/engine/window/ui_overlay.h"
#include "aperture/engine/window/window.h"
#include "aperture/preprocess/background_bake.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/view/camera_controller.h"
#include "aperture/terrain/view/camera_path.h"
#include "aperture/tools/viewer/dynamic_resolution.h"
#include "aperture/tools/viewer/view_lighting.h"

namespace aal {

// Window events of a scripted run (tests, demos), each after frame N counted
// like ViewerOptions::frames (0: none), as if the user had caused it. They
// drive the paths that follow the window: swapchain, renderer and UI
// framebuffers recreated, drawing paused while minimised.
struct WindowScript {
  int resizeAfterFrame = 0;
  int resizeWidth = 0, resizeHeight = 0;  // screen coordinates
  int minimiseAfterFrame = 0;             // restored a few event-loop iterations later
  int toggleVsyncAfterFrame = 0;          // as the panel's vsync checkbox
  int modeAfterFrame = 0;                 // as the panel's shading list: switch to modeAfter
  ShadingMode modeAfter = ShadingMode::Approx;
  // As the panel's direct sun: azimuth sunAzimuthAfterDeg (compass degrees),
  // the elevation kept.
  int sunAzimuthAfterFrame = 0;
  double sunAzimuthAfterDeg = 0;
  // After every scripted frame turn the direct sun by this many degrees of
  // azimuth, the elevation kept (0: not at all): the horizon mode's re-lays
  // under a moving sun (scripts/bench-relay.sh).
  double sunSweepDegPerFrame = 0;
};

// aal-view --temporal: Auto is On except on a CPU device, where the
// reconstruction's full-resolution pass costs more than the pixels it
// spares (docs/viewer.md, "Frame rate").
enum class TemporalReconstruction { Auto, On, Off };

struct ViewerOptions {
  std::string dem;       // the DEM first shown
  std::string aperture;  // its aperture map; empty: cached or baked in the background
  // Its directional horizons (aal-bake --horizons), for the horizon mode;
  // null: none (the mode is not offered). Checked against the DEM already.
  std::shared_ptr<const HorizonMap> horizons;
  int width = 1280, height = 720;  // window size in screen coordinates
  bool vsync = true;
  ShadingMode mode = ShadingMode::Approx;
  bool obscurance = true;  // the obscurance pass on at the start
  int device = -1;
  size_t triangleBudget = kDefaultTriangleBudget;
  double lodErrorPixels = LodSettings{}.maxErrorPixels;
  int anisotropy = kDefaultFootprintProbes;  // FrameSettings::anisotropy at the start
  // Dynamic resolution while the view changes (DynamicResolution); 0: off.
  double targetFps = 30;
  // Its frames rebuilt at full resolution (FrameOutput::temporal) or scaled up.
  TemporalReconstruction temporal = TemporalReconstruction::Auto;
  int bakeAzimuths = 64;
  double exaggeration = 1.0;  // vertical, of this DEM and those dropped later
  // Scripted runs: render `frames` frames (0: run until the window closes),
  // along `cameraPath` when given, then save `screenshot` when given.
  int frames = 0;
  std::optional<CameraPath> cameraPath;
  std::string screenshot;
  double timeoutS = 0;  // > 0: close the window after this many seconds
  // Opened after the first frame as if dropped on the window together
  // (tests, demos).
  std::vector<std::string> dropAfterFirstFrame;
  WindowScript script;
  bool stats = false;                    // print frame and GPU pass times at the end
  std::optional<ViewLighting> lighting;  // initial sun and sky (default from the DEM)
};

// A DEM read from its file; throws InputError when it cannot be.
std::shared_ptr<const Heightfield> loadViewerDem(const std::string& path,
                                                 double exaggeration = 1.0);

class Viewer {
 public:
  // Opens the window (NoDisplayError without a display) and shows `field`.
  Viewer(const ViewerOptions& options, std::shared_ptr<const Heightfield> field);
  ~Viewer();
  Viewer(const Viewer&) = delete;
  Viewer& operator=(const Viewer&) = delete;

  // Runs until the window closes or the scripted frames are done; returns
  // the exit code.
  int run();

 private:
  struct Terrain;
  struct Opening;
  struct Timing;

  // The terrain of `field`: its scene with the aperture map given, else the
  // cached one, else an open sky while the map is baked in the background.
  std::unique_ptr<Terrain> makeTerrain(std::shared_ptr<const Heightfield> field,
                                       const std::string& path, const std::string& aperturePath,
                                       std::shared_ptr<const HorizonMap> horizons);
  // A dropped DEM's terrain, its scene built a share a frame
  // (TerrainScene::staged) with the cached map read on the opening's thread,
  // else an open sky until the bake, started once it is shown: nothing here
  // reads a file or waits.
  std::unique_ptr<Terrain> makeStagedTerrain(PreparedTerrain prepared, const std::string& path);
  // Shows `terrain` in place of the one before, from its default camera,
  // with its horizons laid.
  void showTerrain(std::unique_ptr<Terrain> terrain);
  // Gives the terrain's scene its horizons, if it has any: at once, or
  // `staged`, a share a frame (a finished bake's, TerrainScene::stageHorizons).
  void attachHorizons(bool staged);
  // A dropped DEM is read on a thread and its scene built a share a frame
  // while the terrain before stays on screen (docs/viewer.md); the latest
  // of several drops wins.
  void openDroppedDem(const std::string& path);
  void updateOpening();
  // A dropped DEM's cached horizons, once read, staged.
  void updateHorizonsRead();
  void updateBake();
  void handleKeys();
  void updateCamera(double dtSeconds);
  // Keys or the mouse are moving the camera (it changes every iteration).
  bool cameraDriven() const;
  void drawUi();
  // Whether this iteration must draw: scripted runs always; otherwise only
  // when the view, the settings, the window or the panel changed (an idle
  // viewer uses no CPU).
  bool frameNeeded(const FrameSettings& settings);
  bool drawFrame();
  void recordFrame(VkCommandBuffer cmd, uint32_t imageIndex, const FrameSettings& settings,
                   float resolutionScale);
  FrameSettings frameSettings() const;
  void recreateSwapchain();
  void recreateSurface();
  void saveScreenshot(const std::string& path);
  void finishScriptedFrame();
  void runWindowScript();
  void followScriptedMinimise(bool minimised);
  void setMessage(const std::string& message);
  void printStats() const;

  ViewerOptions options_;
  Window window_;
  Instance instance_;
  std::unique_ptr<Surface> surface_;
  Device device_;
  Swapchain swapchain_;
  FrameSync sync_;
  UiOverlay ui_;
  std::unique_ptr<TerrainRenderer> renderer_;
  std::unique_ptr<Terrain> terrain_;
  std::unique_ptr<Opening> opening_;  // a dropped DEM on its way; null: none
  std::unique_ptr<CameraController> camera_;
  ViewLighting lighting_;
  ShadingMode mode_;
  int anisotropy_;  // FrameSettings::anisotropy (the panel changes it)
  ObscuranceSettings obscurance_;
  bool vsync_;
  bool temporal_;  // frames drawn smaller are rebuilt (ViewerOptions::temporal, resolved)
  bool swapchainStale_ = false;
  std::string message_;
  std::string pendingScreenshot_;          // saved after the next frame
  bool screenshotFromSwapchain_ = false;   // else from the renderer's display image
  Buffer screenshotBuffer_;                // the display image read back for it
  VkExtent2D swapchainFramebuffer_{0, 0};  // window size the swapchain was made for
  int scriptedFrame_ = 0;                  // frames drawn with the real aperture map
  // --minimise-after: event-loop iterations since the window was iconified
  // (-1: not pending), and how many of them found it minimised.
  int minimiseIterations_ = -1;
  int minimisedIterations_ = 0;
  std::unique_ptr<Timing> timing_;
  DynamicResolution resolution_;
  std::optional<FrameSettings> lastDrawn_;  // the settings of the last frame drawn
  float lastScale_ = 1.0f;                  // its resolution scale
  int uiSettleFrames_ = 0;                  // frames still drawn after input (ImGui follows it)
  std::string lastDrawnMessage_;
  double lastBakeFrameS_ = 0;    // when a frame last showed the bake's progress
  uint64_t lastDrawnScene_ = 0;  // TerrainScene::id of the last frame drawn
  bool frameMoving_ = false;     // the last frame drawn showed a changed view
  glm::dvec2 lastCursor_{0.0};
  bool looking_ = false;
};

}  // namespace aal
