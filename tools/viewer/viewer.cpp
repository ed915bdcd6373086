#include "aperture/tools/viewer/viewer.h"

#include <GLFW/glfw3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/frames_in_flight.h"
#include "aperture/engine/vk/image.h"
#include "aperture/engine/vk/vk_check.h"
#include "aperture/preprocess/aperture_cache.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/tools/median.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/viewer/view_panel.h"

namespace aal {

namespace fs = std::filesystem;

struct Viewer::Terrain {
  std::string path;
  std::shared_ptr<const Heightfield> field;
  std::unique_ptr<TerrainScene> scene;
  // Set while the aperture map is baked and then sent to the device.
  std::unique_ptr<BackgroundBake> bake;
  // Once the bake is taken, what the panel says when the map is drawn.
  std::optional<std::string> arrival;
  std::shared_ptr<const HorizonMap> horizons;  // null: no horizon mode
  // A dropped DEM's cached horizons while they are read, after it is shown.
  std::future<std::shared_ptr<const HorizonMap>> horizonsRead;
};

struct Viewer::Timing {
  using Clock = std::chrono::steady_clock;
  Clock::time_point start = Clock::now(), last = start;
  double smoothedFrameMs = 0;
  // Frames drawn and loop iterations that drew nothing (nothing changed);
  // the sum of the resolution scales of the counted frames.
  int drawn = 0, idle = 0;
  double scaleSum = 0;
  int scaled = 0;  // counted frames drawn below full resolution
  std::vector<std::pair<std::string, double>> lastPassMs;
  // Scripted frames, for --stats: wall time from the first counted frame.
  Clock::time_point firstCounted;
  int counted = 0;
  // Frames whose iteration began before the map was drawn (baked, then sent
  // to the device: the iteration that takes the bake too), and their times.
  int whileBaking = 0;
  std::vector<double> bakingMs;
  std::map<std::string, double> passSumsMs;
  int passFrames = 0;
  // Each counted frame's time (its loop iteration), for the median and the
  // longest (--stats: a hitch shows as max / median).
  std::vector<double> countedMs;
  double lastFrameMs = 0;
  // Where the main thread's wall time went in the last drawn frame, and the
  // sums over the counted frames (--stats): kFrameSplit's parts; the loop's
  // rest (input, the panel) is the frame's time less them.
  std::array<double, 5> lastSplitMs{}, splitSumsMs{};
  double restSumMs = 0;
  void split(size_t part, Clock::time_point& since) {
    const Clock::time_point now = Clock::now();
    lastSplitMs[part] = std::chrono::duration<double, std::milli>(now - since).count();
    since = now;
  }

  // Seconds since the last call (at most a quarter second: after a rest the
  // camera and the animated time must not jump).
  double tick() {
    const Clock::time_point now = Clock::now();
    const double dt = std::chrono::duration<double>(now - last).count();
    last = now;
    return std::min(dt, 0.25);
  }
  // A drawn frame took `ms` from the start of its loop iteration.
  void frameDrawn(double ms) {
    lastFrameMs = ms;
    smoothedFrameMs = smoothedFrameMs == 0 ? ms : 0.9 * smoothedFrameMs + 0.1 * ms;
    ++drawn;
  }
  double elapsedS() const { return std::chrono::duration<double>(Clock::now() - start).count(); }
  // Frames drawn while a dropped DEM was read and built (their times), and
  // how long each drop took until its terrain was shown.
  std::vector<double> openingMs;
  std::vector<double> openedS;
};

// A dropped DEM on its way to the screen: read on a thread (GDAL, the
// memory check, the LOD, the sun's place, a cached map), then its scene
// built a share a frame.
struct Viewer::Opening {
  struct Read {
    PreparedTerrain prepared;  // with the cached map when there is one
    GeoPlace place;
  };
  std::string path;
  std::future<Read> read;  // valid while the file is read
  GeoPlace place;
  bool cached = false;               // the map came from the cache
  std::unique_ptr<Terrain> terrain;  // once read: its scene being built
  std::string next;                  // dropped during the read: opened after it
  Timing::Clock::time_point start = Timing::Clock::now();
};

namespace {

// Layout change of a swapchain image (synchronization2).
void swapchainBarrier(VkCommandBuffer cmd, VkImage image, VkImageLayout from, VkImageLayout to,
                      VkPipelineStageFlags2 srcStage, VkAccessFlags2 srcAccess,
                      VkPipelineStageFlags2 dstStage, VkAccessFlags2 dstAccess) {
  const VkImageMemoryBarrier2 barrier{.sType = VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2,
                                      .srcStageMask = srcStage,
                                      .srcAccessMask = srcAccess,
                                      .dstStageMask = dstStage,
                                      .dstAccessMask = dstAccess,
                                      .oldLayout = from,
                                      .newLayout = to,
                                      .srcQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                      .dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED,
                                      .image = image,
                                      .subresourceRange = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                                                           .baseMipLevel = 0,
                                                           .levelCount = 1,
                                                           .baseArrayLayer = 0,
                                                           .layerCount = 1}};
  const VkDependencyInfo dependency{.sType = VK_STRUCTURE_TYPE_DEPENDENCY_INFO,
                                    .imageMemoryBarrierCount = 1,
                                    .pImageMemoryBarriers = &barrier};
  vkCmdPipelineBarrier2(cmd, &dependency);
}

// Copies the swapchain image as drawn (before the UI) into `buffer`; the
// image stays ready for the UI pass.
void readBackSwapchainImage(VkCommandBuffer cmd, VkImage image, VkExtent2D extent,
                            const Buffer& buffer) {
  swapchainBarrier(
      cmd, image, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
      VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT, VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT,
      VK_PIPELINE_STAGE_2_TRANSFER_BIT, VK_ACCESS_2_TRANSFER_READ_BIT);
  const VkBufferImageCopy region{
      .imageSubresource = {.aspectMask = VK_IMAGE_ASPECT_COLOR_BIT,
                           .mipLevel = 0,
                           .baseArrayLayer = 0,
                           .layerCount = 1},
      .imageExtent = {.width = extent.width, .height = extent.height, .depth = 1}};
  vkCmdCopyImageToBuffer(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, buffer.handle(), 1,
                         &region);
  // Only the copy's reads must finish before the UI pass writes.
  swapchainBarrier(cmd, image, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL,
                   VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL, VK_PIPELINE_STAGE_2_TRANSFER_BIT, 0,
                   VK_PIPELINE_STAGE_2_COLOR_ATTACHMENT_OUTPUT_BIT,
                   VK_ACCESS_2_COLOR_ATTACHMENT_READ_BIT | VK_ACCESS_2_COLOR_ATTACHMENT_WRITE_BIT);
}

// aal-view-YYYYMMDD-HHMMSS.png in the current folder, never overwriting: not
// a file, nor a link (even one that leads nowhere), nor anything else of
// that name (writeFrame refuses devices and /dev itself).
std::string nextScreenshotName() {
  const std::time_t now = std::time(nullptr);
  char stamp[32];
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::localtime(&now));
  std::string name = std::string("aal-view-") + stamp + ".png";
  const auto taken = [](const std::string& path) {
    std::error_code error;
    return fs::symlink_status(path, error).type() != fs::file_type::not_found;
  };
  for (int i = 2; taken(name); ++i) {
    name = std::string("aal-view-") + stamp + "-" + std::to_string(i) + ".png";
  }
  return name;
}

const char* presentModeName(VkPresentModeKHR mode) {
  return mode == VK_PRESENT_MODE_FIFO_KHR      ? "fifo (vsync)"
         : mode == VK_PRESENT_MODE_MAILBOX_KHR ? "mailbox"
                                               : "immediate";
}

// --minimise-after: the window is restored once it was seen minimised for
// kMinimisedIterations event-loop iterations, or after kMaxIterations when it
// never was (no window manager to iconify it, as under Xvfb).
constexpr int kMinimisedIterations = 3;
constexpr int kMaxMinimiseIterations = 5;

// Whether two frames show the same picture (the viewer redraws only when
// not; the per-frame GPU data, such as the patch list, follows from these).
bool sameView(const FrameSettings& a, const FrameSettings& b) {
  const auto sameCamera = [](const Camera& x, const Camera& y) {
    return x.position == y.position && x.lookAt == y.lookAt && x.verticalFovDeg == y.verticalFovDeg;
  };
  const auto sameObscurance = [](const ObscuranceSettings& x, const ObscuranceSettings& y) {
    return x.enabled == y.enabled && x.radiusM == y.radiusM && x.samples == y.samples &&
           x.steps == y.steps && x.interleaved == y.interleaved &&
           x.halfResolution == y.halfResolution;
  };
  return sameCamera(a.camera, b.camera) && a.mode == b.mode && a.lighting == b.lighting &&
         a.waterLevelM == b.waterLevelM && sameObscurance(a.obscurance, b.obscurance) &&
         a.albedoValue == b.albedoValue && a.lod.maxErrorPixels == b.lod.maxErrorPixels &&
         a.lod.morph == b.lod.morph && a.anisotropy == b.anisotropy;
}

// How long an idle viewer sleeps between looks at the clock (the --timeout,
// a running bake's progress bar) when no event wakes it.
constexpr double kIdleWaitS = 0.1;
// Level-0 texels of the horizons re-laid a frame at the least (more when the
// sun would leave the shared direction's reach first, engine/horizon_relay.h):
// 2^20, about a tenth of the frame on lavapipe (docs/performance.md).
constexpr uint64_t kViewerHorizonRelayTexels = uint64_t{1} << 20;

// Level-0 texels of a finished background bake's aperture map sent to the
// device a frame (TerrainScene::recordApertureShare), then of its horizons
// (recordHorizonShare, both channels and the slopes: dearer on the device
// than a re-lay's one channel). Chosen on lavapipe, 2048^2, 1280x720: the
// map's 2^20 texels (11 MiB of halves with their levels) cost the frame
// 4-15 ms of the host's time and nothing measurable on the device; the
// horizons' 2^20 texels made frames of 87-118 ms out of 55-60, 2^19 of at
// most 87, 2^18 of at most 74 (docs/performance.md, "A finished bake's
// arrival"). A 4096^2 map arrives in 16 frames, its horizons in 32.
constexpr uint64_t kViewerApertureTexelsPerFrame = uint64_t{1} << 20;
constexpr uint64_t kViewerArrivalHorizonTexels = uint64_t{1} << 19;
// Level-0 texels of a dropped DEM's scene (TerrainScene::recordBuildShare:
// heights and apertures, then the slopes) a frame. Chosen on lavapipe at
// 4096^2 (docs/performance.md, "A dropped DEM"): a share of copies costs the
// frame about 50 ms, one of slopes 20-25 ms; at 2^19 texels the scene took
// 9 s to show, at 2^22 the slopes' frames were 125-160 ms.
constexpr uint64_t kViewerBuildTexelsPerFrame = uint64_t{1} << 20;

// The bake also keeps the sweep's horizons in aal-bake --horizons' 16
// azimuths (8-bit codes) for the horizon mode when the azimuths allow: no
// extra sweep, 16 B per texel on the host (docs/viewer.md).
BakeOptions viewerBakeOptions(int azimuths) {
  BakeOptions options;
  options.azimuths = azimuths;
  options.horizonDirections = kBakeToolHorizonDirections;
  options.horizonBits = kBakeToolHorizonBits;
  options.horizons = azimuths % options.horizonDirections == 0;
  return options;
}

std::shared_ptr<const HorizonMap> sharedHorizons(HorizonMap&& horizons) {
  if (horizons.width == 0) return nullptr;
  return std::make_shared<const HorizonMap>(std::move(horizons));
}

}  // namespace

std::shared_ptr<const Heightfield> loadViewerDem(const std::string& path, double exaggeration) {
  DemLoadOptions options;
  options.exaggeration = exaggeration;
  // The viewer's textures are the render's (lavapipe keeps them in host memory).
  options.peakBytesPerTexel = kRenderBytesPerTexel;
  options.workName = "the viewer's terrain";
  options.memoryHint =
      "cut the DEM (`gdal_translate -srcwin`) or coarsen it (`gdal_translate -outsize 50% 50%`)";
  auto field = std::make_shared<const Heightfield>(loadDem(path, options));
  requireRenderableDem(*field);
  return field;
}

Viewer::Viewer(const ViewerOptions& options, std::shared_ptr<const Heightfield> field)
    : options_(options),
      window_(options.width, options.height, "aal-view"),
      instance_(InstanceOptions{false, Window::requiredInstanceExtensions()}),
      surface_(std::make_unique<Surface>(instance_.handle(), window_)),
      device_(instance_, options.device, {VK_KHR_SWAPCHAIN_EXTENSION_NAME}),
      swapchain_(device_, surface_->handle(), window_.framebufferSize(), options.vsync),
      sync_(device_, swapchain_.imageCount()),
      ui_(instance_, device_, window_, swapchain_),
      lighting_(options.lighting.value_or(defaultViewLighting(*field))),
      mode_(options.mode),
      anisotropy_(options.anisotropy),
      vsync_(options.vsync),
      timing_(std::make_unique<Timing>()),
      resolution_(options.targetFps) {
  swapchainFramebuffer_ = window_.framebufferSize();
  obscurance_.enabled = options.obscurance;
  temporal_ = options.temporal == TemporalReconstruction::On ||
              (options.temporal == TemporalReconstruction::Auto &&
               device_.properties().deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU);
  resolution_.setRebuilt(temporal_);
  renderer_ = std::make_unique<TerrainRenderer>(device_, swapchain_.extent().width,
                                                swapchain_.extent().height, swapchain_.format());
  showTerrain(makeTerrain(std::move(field), options.dem, options.aperture, options.horizons));
}

Viewer::~Viewer() {
  device_.waitIdle();
  // Cancels running bakes (and waits for a DEM being read) before the
  // window and device go.
  opening_.reset();
  terrain_.reset();
}

std::unique_ptr<Viewer::Terrain> Viewer::makeTerrain(std::shared_ptr<const Heightfield> field,
                                                     const std::string& path,
                                                     const std::string& aperturePath,
                                                     std::shared_ptr<const HorizonMap> horizons) {
  auto terrain = std::make_unique<Terrain>();
  terrain->path = path;
  terrain->field = field;
  terrain->horizons = std::move(horizons);
  const BakeOptions bakeOptions = viewerBakeOptions(options_.bakeAzimuths);
  std::string mapPath = aperturePath;
  if (mapPath.empty()) {
    mapPath = findCachedAperture(*field, path, bakeOptions).string();
    // The horizons of the cached map's bake, when it kept them.
    if (!mapPath.empty() && !terrain->horizons && bakeOptions.horizons) {
      terrain->horizons = sharedHorizons(findCachedHorizons(*field, bakeOptions));
    }
  }
  if (!mapPath.empty()) {
    ApertureMapReader reader(mapPath);
    checkApertureMatchesDem(reader.header(), mapPath, *field, path);
    terrain->scene =
        std::make_unique<TerrainScene>(device_, *field, reader, nullptr, options_.triangleBudget);
  } else {
    // Shown at once with an open-sky placeholder (baseline shading) while the
    // map is baked on another thread.
    terrain->scene =
        std::make_unique<TerrainScene>(device_, *field, nullptr, options_.triangleBudget);
    terrain->bake = std::make_unique<BackgroundBake>(field, path, bakeOptions);
  }
  return terrain;
}

std::unique_ptr<Viewer::Terrain> Viewer::makeStagedTerrain(PreparedTerrain prepared,
                                                           const std::string& path) {
  auto terrain = std::make_unique<Terrain>();
  terrain->path = path;
  terrain->field = prepared.field;
  terrain->scene = TerrainScene::staged(device_, std::move(prepared), options_.triangleBudget);
  return terrain;
}

void Viewer::showTerrain(std::unique_ptr<Terrain> terrain) {
  // A frame in flight may still draw the previous terrain: its scene is
  // retired (the bake, on the host, is cancelled now).
  if (terrain_) device_.deletionQueue().retire(std::move(terrain_->scene));
  terrain_ = std::move(terrain);
  attachHorizons(false);
  const VkExtent2D extent = swapchain_.extent();
  camera_ =
      std::make_unique<CameraController>(terrain_->field, double(extent.width) / extent.height);
  window_.setTitle("aal-view - " + fs::path(terrain_->path).filename().string());
}

void Viewer::attachHorizons(bool staged) {
  Terrain& t = *terrain_;
  if (!t.horizons) return;
  try {
    // The pair of directions beside the sun of the moment (the first frame
    // need not re-lay); the renderer re-lays when the sun leaves the pair.
    FrameSettings s;
    applyViewLighting(lighting_, *t.field, s);
    const int first =
        horizonPairFor(t.horizons->directions, sunAzimuthRad(s.lighting.sunDirection), -1);
    if (staged) {
      t.scene->stageHorizons(device_, t.horizons, first);
    } else {
      t.scene->setHorizons(device_, t.horizons, first);
    }
  } catch (const std::exception& e) {
    t.horizons.reset();
    setMessage(std::string("no horizon mode: ") + e.what());
  }
}

void Viewer::openDroppedDem(const std::string& path) {
  if (opening_ && opening_->read.valid()) {
    // A read cannot be stopped: the latest drop waits for it.
    opening_->next = path;
    setMessage("opening " + path + " after " + opening_->path);
    return;
  }
  // A scene still being built for an earlier drop goes (frames in flight
  // may hold its shares).
  if (opening_) device_.deletionQueue().retire(std::move(opening_->terrain->scene));
  opening_ = std::make_unique<Opening>();
  opening_->path = path;
  opening_->read =
      std::async(std::launch::async, [path, exaggeration = options_.exaggeration,
                                      bakeOptions = viewerBakeOptions(options_.bakeAzimuths)] {
        Opening::Read read;
        read.prepared = prepareTerrain(loadViewerDem(path, exaggeration));
        const Heightfield& field = *read.prepared.field;
        read.place = defaultSunPlace(field);
        const fs::path cached = findCachedAperture(field, path, bakeOptions);
        if (!cached.empty()) {
          try {
            ApertureMapReader reader(cached.string());
            checkApertureMatchesDem(reader.header(), cached.string(), field, path);
            read.prepared.aperture = readHalfApertureMap(reader);
          } catch (const std::exception&) {
            // Baked again (the bake replaces an entry it cannot use).
            read.prepared.aperture = HalfApertureMap{};
          }
        }
        return read;
      });
  setMessage("opening " + path);
}

void Viewer::updateOpening() {
  if (!opening_) return;
  Opening& o = *opening_;
  if (o.read.valid()) {
    if (o.read.wait_for(std::chrono::seconds(0)) != std::future_status::ready) return;
    const std::string next = std::exchange(o.next, {});
    try {
      Opening::Read read = o.read.get();
      if (next.empty()) {
        o.place = read.place;
        o.cached = read.prepared.aperture.width != 0;
        // Without --horizons: they were the first DEM's.
        o.terrain = makeStagedTerrain(std::move(read.prepared), o.path);
        return;
      }
    } catch (const std::exception& e) {
      // The terrain before stays.
      setMessage(std::string("cannot open ") + o.path + ": " + e.what());
    }
    opening_.reset();
    if (!next.empty()) openDroppedDem(next);
    return;
  }
  // Until then recordFrame sends the scene's shares.
  if (!o.terrain->scene->built()) return;
  timing_->openedS.push_back(std::chrono::duration<double>(Timing::Clock::now() - o.start).count());
  const GeoPlace place = o.place;
  const std::string path = o.path;
  // Without a cached map the background bake makes one: started now, so
  // that it does not take the cores from the frames that sent the scene.
  const BakeOptions bakeOptions = viewerBakeOptions(options_.bakeAzimuths);
  const bool cached = o.cached;
  if (!cached) {
    o.terrain->bake = std::make_unique<BackgroundBake>(o.terrain->field, path, bakeOptions);
  } else if (bakeOptions.horizons) {
    // The cached horizons are read now, not before: the terrain is shown
    // sooner (1.1 s at 4096^2), and they follow a share a frame.
    o.terrain->horizonsRead =
        std::async(std::launch::async, [field = o.terrain->field, bakeOptions] {
          return sharedHorizons(findCachedHorizons(*field, bakeOptions));
        });
  }
  showTerrain(std::move(o.terrain));
  opening_.reset();
  // The horizon mode waits for horizons when some are coming.
  if (mode_ == ShadingMode::Horizon && !terrain_->bake && !terrain_->horizonsRead.valid()) {
    mode_ = ShadingMode::Approx;
  }
  // The same local solar time at the new place.
  lighting_.hourUtc = std::fmod(
      lighting_.hourUtc - (place.longitudeDeg - lighting_.longitudeDeg) / 15.0 + 48.0, 24.0);
  lighting_.latitudeDeg = place.latitudeDeg;
  lighting_.longitudeDeg = place.longitudeDeg;
  setMessage("opened " + path + (cached ? " (its aperture map from the cache)" : ""));
}

void Viewer::updateHorizonsRead() {
  Terrain& t = *terrain_;
  if (!t.horizonsRead.valid() ||
      t.horizonsRead.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    return;
  }
  try {
    t.horizons = t.horizonsRead.get();
    attachHorizons(true);
  } catch (const std::exception& e) {
    setMessage(std::string("no horizon mode: ") + e.what());
  }
}

void Viewer::updateBake() {
  Terrain& t = *terrain_;
  if (!t.bake) return;
  if (t.arrival) {
    // The map (and the bake's horizons) go to the device a share a frame
    // (recordFrame); the scene draws them once the last share is recorded.
    if (t.scene->apertureStaged() || t.scene->horizonsStaged()) return;
    t.bake.reset();
    setMessage(*std::exchange(t.arrival, std::nullopt));
    return;
  }
  if (!t.bake->finished()) return;
  try {
    BakedAperture baked = t.bake->take();
    if (!t.horizons) t.horizons = sharedHorizons(std::move(baked.horizons));
    t.scene->stageAperture(device_, std::move(baked.map));
    if (!t.scene->hasHorizons()) attachHorizons(true);  // the bake's own
    t.arrival = "aperture map ready" + (baked.path.empty() ? std::string(" (not cached)")
                                                           : ", cached as " + baked.path.string());
  } catch (const std::exception& e) {
    setMessage(std::string("aperture bake failed: ") + e.what());
    t.bake.reset();
  }
}

void Viewer::handleKeys() {
  for (int key : window_.takeKeyPresses()) {
    if (ui_.wantsKeyboard()) continue;
    const VkExtent2D extent = swapchain_.extent();
    if (key == GLFW_KEY_F) camera_->frame(double(extent.width) / extent.height);
    if (key == GLFW_KEY_O) {
      camera_->setMode(camera_->mode() == CameraMode::Fly ? CameraMode::Orbit : CameraMode::Fly);
    }
    if (key == GLFW_KEY_F12) pendingScreenshot_ = nextScreenshotName();
  }
  for (const std::string& path : window_.takeDroppedPaths()) openDroppedDem(path);
}

bool Viewer::cameraDriven() const {
  if (looking_) return true;
  if (!ui_.wantsKeyboard()) {
    for (int key : {GLFW_KEY_W, GLFW_KEY_A, GLFW_KEY_S, GLFW_KEY_D, GLFW_KEY_Q, GLFW_KEY_E}) {
      if (window_.keyDown(key)) return true;
    }
  }
  return window_.mouseButtonDown(GLFW_MOUSE_BUTTON_RIGHT) && !ui_.wantsMouse();
}

void Viewer::updateCamera(double dtSeconds) {
  const CameraPath* path = options_.cameraPath ? &*options_.cameraPath : nullptr;
  if (path && options_.frames > 0) {
    camera_->setCamera(path->at(path->frameTime(scriptedFrame_, options_.frames)));
    return;
  }
  if (path && timing_->elapsedS() <= path->endS() - path->startS()) {
    camera_->setCamera(path->at(path->startS() + timing_->elapsedS()));
    return;
  }
  CameraInput in;
  in.dtSeconds = dtSeconds;
  const bool rightDown = window_.mouseButtonDown(GLFW_MOUSE_BUTTON_RIGHT);
  if (rightDown && !looking_ && !ui_.wantsMouse()) {
    looking_ = true;
    window_.setCursorCaptured(true);
    lastCursor_ = window_.cursorPosition();
  }
  if (!rightDown && looking_) {
    looking_ = false;
    window_.setCursorCaptured(false);
  }
  const glm::dvec2 cursor = window_.cursorPosition();
  if (looking_) in.lookPixels = cursor - lastCursor_;
  lastCursor_ = cursor;
  const double wheel = window_.takeWheelSteps();
  if (!ui_.wantsMouse()) in.wheelSteps = wheel;
  if (!ui_.wantsKeyboard()) {
    auto axis = [&](int plus, int minus) {
      return (window_.keyDown(plus) ? 1.0 : 0.0) - (window_.keyDown(minus) ? 1.0 : 0.0);
    };
    in.move = {axis(GLFW_KEY_D, GLFW_KEY_A), axis(GLFW_KEY_W, GLFW_KEY_S),
               axis(GLFW_KEY_E, GLFW_KEY_Q)};
    in.fast = window_.keyDown(GLFW_KEY_LEFT_SHIFT) || window_.keyDown(GLFW_KEY_RIGHT_SHIFT);
  }
  camera_->update(in);
}

void Viewer::drawUi() {
  ui_.beginFrame();
  const Heightfield& field = *terrain_->field;
  ViewPanelModel model{lighting_, mode_, anisotropy_, obscurance_, vsync_, temporal_};
  if (!terrain_->scene->hasHorizons()) {
    model.horizonsMissing = terrain_->horizonsRead.valid() ? "being read"
                            : terrain_->bake && viewerBakeOptions(options_.bakeAzimuths).horizons
                                ? "after the bake"
                                : "needs --horizons FILE";
  }
  model.cameraMode = camera_->mode();
  model.demName = fs::path(terrain_->path).filename().string();
  model.demWidth = field.width;
  model.demHeight = field.height;
  model.triangles = renderer_->lodSelection().triangles;  // the last frame's LOD
  if (terrain_->bake) model.bakeProgress = terrain_->bake->progress();
  model.message = message_;
  model.frameMs = timing_->smoothedFrameMs;
  model.framesPerSecond = model.frameMs > 0 ? 1e3 / model.frameMs : 0;
  model.passMs = timing_->lastPassMs;
  model.resolutionScale = lastScale_;
  model.targetFps = resolution_.targetFps();
  model.speedMps = camera_->speedMps();
  model.heightAboveGroundM = camera_->heightAboveGround();
  const glm::dvec2 extent = demExtentM(field);
  model.defaultObscuranceRadiusM =
      defaultObscuranceRadiusM({field.cellSizeXM, field.cellSizeYM}, extent);
  model.maxObscuranceRadiusM = static_cast<float>(std::min(extent.x, extent.y));
  const ViewPanelActions actions = drawViewPanel(model);
  const VkExtent2D size = swapchain_.extent();
  if (actions.frameDem) camera_->frame(double(size.width) / size.height);
  if (actions.toggleOrbit) {
    camera_->setMode(camera_->mode() == CameraMode::Fly ? CameraMode::Orbit : CameraMode::Fly);
  }
  if (actions.screenshot) pendingScreenshot_ = nextScreenshotName();
  if (actions.vsyncChanged) swapchainStale_ = true;
  // The history holds frames of the other way: start it again.
  if (actions.temporalChanged) {
    renderer_->restartTemporal();
    resolution_.setRebuilt(temporal_);
  }
  if (model.targetFps != resolution_.targetFps()) resolution_.setTargetFps(model.targetFps);
}

FrameSettings Viewer::frameSettings() const {
  FrameSettings s;
  s.camera = camera_->camera();
  // The placeholder aperture is an open sky: only the baselines are honest.
  s.mode = terrain_->bake ? ShadingMode::BaselineLambert : mode_;
  // The panel offers the horizon mode only with horizons; a stale choice draws approx.
  if (s.mode == ShadingMode::Horizon && !terrain_->scene->hasHorizons())
    s.mode = ShadingMode::Approx;
  applyViewLighting(lighting_, *terrain_->field, s);
  s.obscurance = obscurance_;
  s.anisotropy = anisotropy_;
  s.lod.maxErrorPixels = options_.lodErrorPixels;
  // A re-lay of the horizons spread over frames, none a stall
  // (docs/rendering.md, "Where the horizons lie").
  s.horizonRelayTexelsPerFrame = kViewerHorizonRelayTexels;
  return s;
}

void Viewer::recordFrame(VkCommandBuffer cmd, uint32_t imageIndex, const FrameSettings& settings,
                         float resolutionScale) {
  // The renderer's last pass writes the swapchain image itself (no copy), or
  // scales its smaller picture up into it; it is left ready for the UI pass.
  FrameOutput output;
  output.image = swapchain_.image(imageIndex);
  output.view = swapchain_.view(imageIndex);
  output.resolutionScale = resolutionScale;
  output.frameSlot = sync_.slot();
  // Drawn smaller while the view moves: rebuilt from the frames before.
  output.temporal = resolutionScale < 1.0f && temporal_;
  // A finished bake's map, then its horizons, go up a share a frame into
  // images no frame reads yet: no frame waits for all of it, nor pays for
  // both at once.
  // A dropped DEM's scene is built the same way, while this one is drawn.
  if (opening_ && opening_->terrain) {
    opening_->terrain->scene->recordBuildShare(device_, cmd, kViewerBuildTexelsPerFrame);
  } else if (terrain_->scene->apertureStaged()) {
    terrain_->scene->recordApertureShare(cmd, kViewerApertureTexelsPerFrame);
  } else {
    terrain_->scene->recordHorizonShare(device_, cmd, kViewerArrivalHorizonTexels);
  }
  renderer_->record(cmd, *terrain_->scene, settings, output);
  if (!pendingScreenshot_.empty()) {
    // What is presented (without the panel); the renderer's display image
    // where the swapchain cannot be read (it then holds the same picture:
    // record it once more there).
    const VkExtent2D extent = swapchain_.extent();
    screenshotBuffer_ = Buffer(device_, VkDeviceSize(extent.width) * extent.height * 4,
                               VK_BUFFER_USAGE_TRANSFER_DST_BIT, MemoryIntent::Readback);
    screenshotFromSwapchain_ = swapchain_.readable();
    if (screenshotFromSwapchain_) {
      readBackSwapchainImage(cmd, output.image, extent, screenshotBuffer_);
    } else {
      renderer_->record(cmd, *terrain_->scene, settings,
                        FrameOutput{.frameSlot = output.frameSlot});
      copyImageToBuffer(cmd, renderer_->displayImage(), screenshotBuffer_);
    }
  }
  ui_.record(cmd, imageIndex);
}

bool Viewer::frameNeeded(const FrameSettings& settings) {
  if (options_.frames > 0 || swapchainStale_ || !pendingScreenshot_.empty()) return true;
  if (!lastDrawn_ || !sameView(settings, *lastDrawn_) || lastScale_ < 1.0f) return true;
  if (terrain_->scene->id() != lastDrawnScene_ || message_ != lastDrawnMessage_) return true;
  // Each frame sends a share of a finished bake's map and horizons, or of a
  // dropped DEM's scene.
  if (terrain_->scene->apertureStaged() || terrain_->scene->horizonsStaged()) return true;
  if (opening_ && opening_->terrain) return true;
  // Input reaches the panel too: draw a few frames for ImGui to follow it.
  if (window_.takeActivity()) uiSettleFrames_ = 3;
  if (uiSettleFrames_ > 0) {
    --uiSettleFrames_;
    return true;
  }
  // A running bake's progress bar moves a few times a second.
  return terrain_->bake && timing_->elapsedS() - lastBakeFrameS_ > 0.25;
}

// The parts of drawFrame that Timing::split measures.
constexpr std::array<const char*, 5> kFrameSplit = {"wait for the slot's frame", "acquire",
                                                    "prepare + record", "submit", "present"};

bool Viewer::drawFrame() {
  Timing::Clock::time_point since = Timing::Clock::now();
  timing_->lastSplitMs.fill(0);
  sync_.waitForFrameSlot();
  timing_->split(0, since);
  // The pass times of the frame that last used this slot: it has completed
  // (kFramesInFlight frames back).
  timing_->lastPassMs = renderer_->passMilliseconds(sync_.slot());
  uint32_t imageIndex = 0;
  SwapchainStatus status = swapchain_.acquire(sync_.acquired(), &imageIndex);
  if (status == SwapchainStatus::OutOfDate) swapchainStale_ = true;
  if (status == SwapchainStatus::SurfaceLost) recreateSurface();
  if (status != SwapchainStatus::Ok) return false;
  timing_->split(1, since);

  FrameSettings settings = frameSettings();
  // The view changes while the settings do (camera, time of day, panel):
  // then the dynamic resolution keeps the frame rate and the obscurance pass
  // reuses earlier frames' samples; a screenshot and the first frame at rest
  // get every pixel and every sample.
  const bool moving = lastDrawn_ && !sameView(settings, *lastDrawn_);
  settings.obscurance.history = moving && pendingScreenshot_.empty()
                                    ? ObscuranceSettings::History::Reuse
                                    : ObscuranceSettings::History::Refresh;
  const float scale = pendingScreenshot_.empty() ? resolution_.scaleFor(moving) : 1.0f;
  recordFrame(sync_.beginCommands(), imageIndex, settings, scale);
  timing_->split(2, since);
  sync_.submit(imageIndex);
  timing_->split(3, since);
  lastDrawn_ = settings;
  lastScale_ = scale;
  lastDrawnScene_ = terrain_->scene->id();
  lastDrawnMessage_ = message_;
  if (terrain_->bake) lastBakeFrameS_ = timing_->elapsedS();
  frameMoving_ = moving;
  status = swapchain_.present(imageIndex, sync_.rendered(imageIndex));
  timing_->split(4, since);
  if (status == SwapchainStatus::OutOfDate) swapchainStale_ = true;
  if (status == SwapchainStatus::SurfaceLost) recreateSurface();
  if (!pendingScreenshot_.empty()) saveScreenshot(std::exchange(pendingScreenshot_, {}));
  return true;
}

void Viewer::saveScreenshot(const std::string& path) {
  sync_.waitForSubmittedFrames();
  FrameResult frame;
  frame.width = renderer_->width();
  frame.height = renderer_->height();
  frame.display.resize(size_t(frame.width) * frame.height * 4);
  screenshotBuffer_.read(frame.display.data(), frame.display.size());
  screenshotBuffer_ = Buffer();
  if (swapchain_.format() == VK_FORMAT_B8G8R8A8_UNORM) {  // either source holds BGRA
    for (size_t i = 0; i < frame.display.size(); i += 4) {
      std::swap(frame.display[i], frame.display[i + 2]);
    }
  }
  try {
    writeFrame(path, frame);
    setMessage("saved screenshot " + path);
  } catch (const std::exception& e) {
    setMessage(std::string("screenshot failed: ") + e.what());
    if (path == options_.screenshot) throw;
  }
}

void Viewer::recreateSwapchain() {
  device_.waitIdle();
  swapchainFramebuffer_ = window_.framebufferSize();
  const VkPresentModeKHR before = swapchain_.presentMode();
  swapchain_.recreate(swapchainFramebuffer_, vsync_);
  // Shows whether the vsync switch took effect (the surface may offer FIFO only).
  if (swapchain_.presentMode() != before) {
    setMessage(std::string("present mode ") + presentModeName(before) + " -> " +
               presentModeName(swapchain_.presentMode()));
  }
  ui_.onSwapchainRecreated(swapchain_);
  sync_.resize(swapchain_.imageCount());
  const VkExtent2D extent = swapchain_.extent();
  if (renderer_->width() != extent.width || renderer_->height() != extent.height ||
      renderer_->displayImage().desc().format != swapchain_.format()) {
    // Its targets go with the frames that drew into them.
    device_.deletionQueue().retire(
        std::exchange(renderer_, std::make_unique<TerrainRenderer>(
                                     device_, extent.width, extent.height, swapchain_.format())));
  }
  swapchainStale_ = false;
}

void Viewer::recreateSurface() {
  device_.waitIdle();
  auto fresh = std::make_unique<Surface>(instance_.handle(), window_);
  swapchain_.recreate(fresh->handle(), window_.framebufferSize(), vsync_);
  surface_ = std::move(fresh);
  swapchainStale_ = true;  // the rest follows the new swapchain
}

void Viewer::finishScriptedFrame() {
  for (const std::string& path : std::exchange(options_.dropAfterFirstFrame, {})) {
    openDroppedDem(path);
  }
  // Scripted frames and window events wait for a dropped DEM, the bake and
  // horizons on their way.
  if (opening_ || terrain_->bake || terrain_->horizonsRead.valid() ||
      terrain_->scene->horizonsStaged()) {
    return;
  }
  ++scriptedFrame_;
  runWindowScript();
  if (options_.frames <= 0) return;
  Timing& t = *timing_;
  if (t.counted == 0) t.firstCounted = Timing::Clock::now();
  // The first counted frame's set-up is left out, as in the mean.
  if (t.counted > 0) {
    t.countedMs.push_back(t.lastFrameMs);
    double parts = 0;
    for (size_t i = 0; i < t.splitSumsMs.size(); ++i) {
      t.splitSumsMs[i] += t.lastSplitMs[i];
      parts += t.lastSplitMs[i];
    }
    t.restSumMs += t.lastFrameMs - parts;
  }
  ++t.counted;
  for (const auto& [pass, ms] : t.lastPassMs) t.passSumsMs[pass] += ms;
  if (!t.lastPassMs.empty()) ++t.passFrames;
  t.scaleSum += lastScale_;
  if (lastScale_ < 1.0f) ++t.scaled;
  if (scriptedFrame_ >= options_.frames) window_.requestClose();
}

void Viewer::runWindowScript() {
  const WindowScript& s = options_.script;
  if (scriptedFrame_ == s.resizeAfterFrame) {
    // The next iteration sees the new framebuffer size and recreates the rest.
    setMessage("resizing the window to " + std::to_string(s.resizeWidth) + "x" +
               std::to_string(s.resizeHeight));
    window_.setSize(s.resizeWidth, s.resizeHeight);
  }
  if (scriptedFrame_ == s.toggleVsyncAfterFrame) {
    vsync_ = !vsync_;
    swapchainStale_ = true;
  }
  if (scriptedFrame_ == s.modeAfterFrame) {
    // As the panel: the horizon mode only where it is offered.
    if (s.modeAfter == ShadingMode::Horizon && !terrain_->scene->hasHorizons()) {
      setMessage("the horizon mode is not offered: no directional horizons");
    } else {
      mode_ = s.modeAfter;
      setMessage("switched the shading mode");
    }
  }
  if (scriptedFrame_ == s.sunAzimuthAfterFrame) {
    // As the panel's direct sun: the elevation the sun has now.
    lighting_.sunElevationDeg = viewSun(lighting_).elevationDeg;
    lighting_.fromTime = false;
    lighting_.sunAzimuthDeg = s.sunAzimuthAfterDeg;
    char text[64];
    std::snprintf(text, sizeof text, "moved the sun to azimuth %g degrees", s.sunAzimuthAfterDeg);
    setMessage(text);
  }
  if (s.sunSweepDegPerFrame != 0) {
    const SolarPosition sun = viewSun(lighting_);
    lighting_.sunElevationDeg = sun.elevationDeg;
    lighting_.sunAzimuthDeg = sun.azimuthDeg + s.sunSweepDegPerFrame;
    lighting_.sunAzimuthDeg -= 360.0 * std::floor(lighting_.sunAzimuthDeg / 360.0);
    lighting_.fromTime = false;
  }
  if (scriptedFrame_ == s.minimiseAfterFrame) {
    setMessage("minimising the window");
    window_.iconify();
    minimiseIterations_ = 0;
    minimisedIterations_ = 0;
  }
}

void Viewer::followScriptedMinimise(bool minimised) {
  if (minimiseIterations_ < 0) return;
  ++minimiseIterations_;
  if (minimised) ++minimisedIterations_;
  if (minimisedIterations_ < kMinimisedIterations && minimiseIterations_ < kMaxMinimiseIterations) {
    return;
  }
  window_.restore();
  setMessage(minimisedIterations_ > 0
                 ? "restored the window after " + std::to_string(minimisedIterations_) +
                       " event-loop iterations minimised without drawing"
                 : "restored the window: it was not minimised (no window manager?)");
  minimiseIterations_ = -1;
}

void Viewer::setMessage(const std::string& message) {
  message_ = message;
  std::fprintf(stderr, "aal-view: %s\n", message.c_str());
}

void Viewer::printStats() const {
  const Timing& t = *timing_;
  const VkExtent2D extent = swapchain_.extent();
  std::printf("device     %s\n", device_.name().c_str());
  std::printf("size       %ux%u\n", extent.width, extent.height);
  std::printf("present    %s\n", presentModeName(swapchain_.presentMode()));
  std::printf("triangles  %zu (last frame)\n", renderer_->lodSelection().triangles);
  if (terrain_->scene->hasHorizons()) {
    // Each a hitch: the horizons uploaded again (docs/viewer.md).
    std::printf("horizons   re-laid %llu times for the sun (directions %d and %d now)\n",
                static_cast<unsigned long long>(terrain_->scene->horizonRelays()),
                terrain_->scene->horizonFirst(),
                (terrain_->scene->horizonFirst() + 1) % terrain_->scene->horizonDirections());
  }
  std::printf("frames     %d\n", t.counted);
  std::printf("baking     %d frames drawn while the aperture map was baked", t.whileBaking);
  if (!t.bakingMs.empty()) {
    // Its arrival among them: a stall shows as the longest.
    std::vector<double> ms = t.bakingMs;
    std::sort(ms.begin(), ms.end());
    std::printf(" and sent (median %.1f ms, longest %.1f ms)", ms[ms.size() / 2], ms.back());
  }
  std::printf("\n");
  if (!t.openedS.empty() || !t.openingMs.empty()) {
    std::printf("opening    %zu frames drawn while a dropped DEM was read and built",
                t.openingMs.size());
    if (!t.openingMs.empty()) {
      std::vector<double> ms = t.openingMs;
      std::sort(ms.begin(), ms.end());
      std::printf(" (median %.1f ms, longest %.1f ms)", ms[ms.size() / 2], ms.back());
    }
    for (double seconds : t.openedS) std::printf("; shown after %.2f s", seconds);
    std::printf("\n");
  }
  std::printf("drawn      %d frames, %d idle iterations (nothing changed, nothing drawn)\n",
              t.drawn, t.idle);
  if (t.counted > 0) {
    std::printf(
        "resolution %.0f %% of the pixels' width on average, %d frames reduced (target "
        "%.0f fps%s)\n",
        100 * t.scaleSum / t.counted, t.scaled, resolution_.targetFps(),
        resolution_.targetFps() > 0 ? "" : ": off");
  }
  if (t.counted > 1) {
    // Intervals between counted frames: the first frame's set-up is excluded.
    const double seconds =
        std::chrono::duration<double>(Timing::Clock::now() - t.firstCounted).count();
    const double ms = seconds * 1e3 / (t.counted - 1);
    std::printf("frame      %.2f ms (%.2f fps)\n", ms, 1e3 / ms);
  }
  if (!t.countedMs.empty()) {
    const double middle = median(t.countedMs);
    const double longest = *std::max_element(t.countedMs.begin(), t.countedMs.end());
    std::printf("frames ms  median %.2f, max %.2f (max/median %.2f) over %zu frames\n", middle,
                longest, longest / middle, t.countedMs.size());
  }
  if (t.countedMs.size() > 0) {
    // The main thread's wall time: a CPU device shades while the loop waits
    // in "wait" or "present" (which waits for the frame to be drawn before
    // it copies the picture to the window).
    const double n = double(t.countedMs.size());
    std::printf("main thread, mean ms per frame:");
    for (size_t i = 0; i < kFrameSplit.size(); ++i) {
      std::printf(" %s %.2f,", kFrameSplit[i], t.splitSumsMs[i] / n);
    }
    std::printf(" the rest of the loop (input and panel) %.2f\n", t.restSumMs / n);
  }
  // Timestamps tell a GPU's passes apart; a CPU device writes them when its
  // queue thread reaches them, before its worker threads shade the draws
  // (engine/vk/serial_pass_timer.h): aal-render --pass-profile tells them.
  const bool cpu = device_.properties().deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
  double total = 0;
  for (const auto& [pass, sum] : t.passSumsMs) {
    std::printf("gpu %-10s %8.3f ms\n", pass.c_str(), sum / std::max(t.passFrames, 1));
    total += sum / std::max(t.passFrames, 1);
  }
  std::printf("gpu total      %8.3f ms%s\n", total,
              cpu ? " (timestamps of a CPU device: not the passes' cost; see aal-render "
                    "--pass-profile)"
                  : "");
}

int Viewer::run() {
  while (!window_.shouldClose()) {
    window_.pollEvents();
    const Timing::Clock::time_point start = Timing::Clock::now();
    const double dt = timing_->tick();
    if (options_.timeoutS > 0 && timing_->elapsedS() > options_.timeoutS) window_.requestClose();
    const VkExtent2D framebuffer = window_.framebufferSize();
    const bool minimised = framebuffer.width == 0 || framebuffer.height == 0 || window_.iconified();
    followScriptedMinimise(minimised);
    if (minimised) {
      window_.waitEvents(0.1);  // minimised: no frames, but the timeout and the bake go on
      continue;
    }
    if (swapchainStale_ || framebuffer.width != swapchainFramebuffer_.width ||
        framebuffer.height != swapchainFramebuffer_.height) {
      recreateSwapchain();
    }
    handleKeys();
    const bool baking = terrain_->bake != nullptr;
    const bool opening = opening_ != nullptr;
    updateOpening();
    updateHorizonsRead();
    updateBake();
    advanceViewTime(lighting_, dt);
    updateCamera(dt);
    // Moving keys held or the mouse looking around move the camera every
    // iteration; otherwise an unchanged view waits for the next event.
    if (!cameraDriven() && !frameNeeded(frameSettings())) {
      ++timing_->idle;
      window_.waitEvents(kIdleWaitS);
      continue;
    }
    drawUi();
    const bool lastScripted =
        options_.frames > 0 && !terrain_->bake && scriptedFrame_ == options_.frames - 1;
    if (lastScripted && !options_.screenshot.empty()) pendingScreenshot_ = options_.screenshot;
    if (!drawFrame()) continue;
    const double frameMs =
        std::chrono::duration<double, std::milli>(Timing::Clock::now() - start).count();
    timing_->frameDrawn(frameMs);
    resolution_.frameFinished(frameMs, frameMoving_);
    if (opening) timing_->openingMs.push_back(frameMs);
    if (baking) {
      ++timing_->whileBaking;
      // The first frame's set-up (pipelines) is left out, as in the mean.
      if (timing_->drawn > 1) timing_->bakingMs.push_back(frameMs);
    }
    finishScriptedFrame();
  }
  device_.waitIdle();
  if (terrain_->bake && !terrain_->bake->finished()) {
    setMessage("closed during the aperture bake: cancelled, nothing cached");
  }
  if (options_.stats) printStats();
  // Under AAL_VALIDATION=1 any validation message fails the run (tests).
  if (instance_.validationEnabled()) {
    const size_t messages = instance_.validationLog().count();
    std::fprintf(stderr, "aal-view: validation on, %zu messages\n", messages);
    if (messages > 0) return 1;
  }
  return 0;
}

}  // namespace aal
