// aal-view: fly over a DEM with live sun, sky and lighting controls.
#include <exception>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/engine/screenshot.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/tools/horizon_option.h"
#include "aperture/tools/options/camera_options.h"
#include "aperture/tools/options/gpu_options.h"
#include "aperture/tools/options/sun_options.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"
#include "aperture/tools/viewer/viewer.h"

namespace {

constexpr const char* kControls = R"(Controls:
  right mouse (hold)  look around (orbit: turn around the pivot)
  W A S D             move forward, left, back, right (orbit: move the pivot)
  Q / E               down / up
  Shift               4x faster
  mouse wheel         fly speed (orbit: zoom); speed also scales with the height above ground
  F                   frame the whole DEM
  O                   switch between fly and orbit mode
  F12                 save a screenshot (aal-view-DATE-TIME.png in the current folder)
  drop a DEM file     open it (a file that cannot be read leaves the current terrain)
The panel sets the date, time of day (play/pause), place or a direct sun azimuth/elevation,
sun radius, turbidity, sun/sky intensity, exposure, shading mode (horizon with --horizons),
obscurance, vsync,
and shows the frame rate and GPU time per pass. See docs/viewer.md.)";

struct Options {
  std::string dem, aperture, horizons, cameraPath, screenshot, size = "1280x720";
  std::vector<std::string> drop;
  std::optional<std::string> resizeAfter, minimiseAfter, toggleVsyncAfter, modeAfter,
      sunAzimuthAfter;  // test hooks
  std::string mode = "approx";
  aal::SunOptions sun;
  std::optional<double> waterLevelM;
  double exaggeration = 1.0;
  std::optional<int> frames;
  double timeoutS = 0;
  bool noVsync = false, stats = false, noObscurance = false;
  int azimuths = 64;
  double sunSweepDeg = 0;
  aal::GpuOptions gpu;
  std::optional<double> targetFps;
  std::string temporal = "auto";
};

// Scripted-run options checked before anything is loaded or opened.
void checkScript(const Options& o) {
  if (o.frames && *o.frames < 1) {
    throw aal::InputError("--frames must be at least 1, got " + std::to_string(*o.frames));
  }
  // The screenshot against every file read: the DEMs' (a VRT's sources too),
  // a tiled aperture map's.
  aal::NamedPaths inputs = aal::inputFiles("DEM", o.dem, /*raster=*/true);
  aal::append(inputs, aal::inputFiles("--aperture", o.aperture));
  for (const std::string& path : o.drop) {
    aal::append(inputs, aal::inputFiles("--drop", path, /*raster=*/true));
  }
  inputs.push_back({"--horizons", o.horizons});
  inputs.push_back({"--camera-path", o.cameraPath});
  aal::checkDistinctFiles(inputs, {{"--screenshot", o.screenshot}});
  if (!o.screenshot.empty()) {
    if (!o.frames) throw aal::InputError("--screenshot needs --frames N (saved after frame N)");
    if (!aal::isSupportedImageOutput(o.screenshot) || aal::wantsLinearOutput(o.screenshot)) {
      throw aal::InputError("--screenshot " + o.screenshot + " must end in .png");
    }
    aal::requireWritableOutput(o.screenshot);
  }
  if (o.sun.azimuthDeg.has_value() != o.sun.elevationDeg.has_value()) {
    throw aal::InputError("give --sun-azimuth and --sun-elevation together");
  }
}

// The frame of a --*-after test hook: "FRAME", or "FRAME:VALUE" when
// `value` is wanted (it receives VALUE). FRAME counts like --frames, and a
// run of N frames ends after frame N, so FRAME must be below N.
int parseAfterFrame(const std::string& option, const std::string& text,
                    const std::optional<int>& frames, std::string* value = nullptr) {
  const size_t colon = text.find(':');
  const std::string frame = text.substr(0, colon);
  const std::string form = value ? "FRAME:VALUE" : "FRAME";
  if ((colon == std::string::npos) != (value == nullptr) || frame.empty() ||
      frame.find_first_not_of("0123456789") != std::string::npos || frame.size() > 9 ||
      std::stoi(frame) < 1) {
    throw aal::InputError(option + " must be " + form +
                          " with FRAME a positive frame number, got '" + text + "'");
  }
  const int n = std::stoi(frame);
  if (frames && n >= *frames) {
    throw aal::InputError(option + " " + text + ": the run ends after frame " +
                          std::to_string(*frames) + " (--frames)");
  }
  if (value) *value = text.substr(colon + 1);
  return n;
}

aal::WindowScript windowScript(const Options& o) {
  aal::WindowScript s;
  if (o.resizeAfter) {
    std::string size;
    s.resizeAfterFrame = parseAfterFrame("--resize-after", *o.resizeAfter, o.frames, &size);
    const auto [width, height] = aal::parseSize(size, "--resize-after's size");
    s.resizeWidth = static_cast<int>(width);
    s.resizeHeight = static_cast<int>(height);
  }
  if (o.minimiseAfter) {
    s.minimiseAfterFrame = parseAfterFrame("--minimise-after", *o.minimiseAfter, o.frames);
  }
  if (o.toggleVsyncAfter) {
    s.toggleVsyncAfterFrame =
        parseAfterFrame("--toggle-vsync-after", *o.toggleVsyncAfter, o.frames);
  }
  if (o.modeAfter) {
    std::string mode;
    s.modeAfterFrame = parseAfterFrame("--mode-after", *o.modeAfter, o.frames, &mode);
    const auto known = aal::toolShadingModes().find(mode);
    if (known == aal::toolShadingModes().end()) {
      throw aal::InputError("--mode-after " + *o.modeAfter + ": no shading mode '" + mode + "'");
    }
    s.modeAfter = known->second;
  }
  if (o.sunAzimuthAfter) {
    std::string degrees;
    s.sunAzimuthAfterFrame =
        parseAfterFrame("--sun-azimuth-after", *o.sunAzimuthAfter, o.frames, &degrees);
    size_t used = 0;
    double value = 0;
    try {
      value = std::stod(degrees, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != degrees.size() || !(value >= -360.0 && value <= 720.0)) {
      throw aal::InputError("--sun-azimuth-after " + *o.sunAzimuthAfter +
                            ": the azimuth must be degrees in [-360, 720]");
    }
    s.sunAzimuthAfterDeg = value;
  }
  s.sunSweepDegPerFrame = o.sunSweepDeg;
  return s;
}

aal::ViewLighting initialLighting(const Options& o, const aal::Heightfield& field) {
  aal::ViewLighting l = aal::defaultViewLighting(field);
  if (o.sun.latitudeDeg) l.latitudeDeg = *o.sun.latitudeDeg;
  if (o.sun.longitudeDeg) l.longitudeDeg = *o.sun.longitudeDeg;
  if (!o.sun.time.empty()) {
    const std::optional<aal::UtcTime> t = aal::parseIso8601Utc(o.sun.time);
    if (!t) throw aal::InputError("--time must be ISO 8601, e.g. 2024-06-21T12:00:00Z");
    l.year = t->year;
    l.month = t->month;
    l.day = t->day;
    l.hourUtc = t->hour + t->minute / 60.0 + t->second / 3600.0;
  }
  if (o.sun.azimuthDeg) {
    l.fromTime = false;
    l.sunAzimuthDeg = *o.sun.azimuthDeg;
    l.sunElevationDeg = *o.sun.elevationDeg;
  }
  // The level is in the DEM's metres; the drawn heights are exaggerated.
  if (o.waterLevelM) l.waterLevelM = *o.waterLevelM * o.exaggeration;
  return l;
}

int run(const Options& o) {
  checkScript(o);
  aal::ViewerOptions v;
  v.dem = o.dem;
  v.aperture = o.aperture;
  const auto [width, height] = aal::parseSize(o.size);
  v.width = static_cast<int>(width);
  v.height = static_cast<int>(height);
  v.vsync = !o.noVsync;
  v.mode = aal::toolShadingModes().at(o.mode);
  v.obscurance = !o.noObscurance;
  v.device = o.gpu.device;
  v.triangleBudget = o.gpu.triangleBudget;
  v.lodErrorPixels = o.gpu.lodErrorPixels;
  v.anisotropy = o.gpu.anisotropy;
  // Scripted runs measure and take screenshots: full resolution unless asked.
  v.targetFps = o.targetFps.value_or(o.frames ? 0.0 : 30.0);
  v.temporal = o.temporal == "on"    ? aal::TemporalReconstruction::On
               : o.temporal == "off" ? aal::TemporalReconstruction::Off
                                     : aal::TemporalReconstruction::Auto;
  v.bakeAzimuths = o.azimuths;
  v.exaggeration = o.exaggeration;
  v.frames = o.frames.value_or(0);
  if (!o.cameraPath.empty()) v.cameraPath = aal::CameraPath::load(o.cameraPath);
  v.screenshot = o.screenshot;
  v.timeoutS = o.timeoutS;
  v.dropAfterFirstFrame = o.drop;
  v.script = windowScript(o);
  if (o.horizons.empty() && v.mode == aal::ShadingMode::Horizon) {
    throw aal::InputError("--mode horizon needs --horizons FILE (aal-bake --horizons)");
  }
  // Later, the viewer's own bake may have kept them (not for --aperture).
  if (o.horizons.empty() && !o.aperture.empty() && v.script.modeAfterFrame > 0 &&
      v.script.modeAfter == aal::ShadingMode::Horizon) {
    throw aal::InputError("--mode-after " + *o.modeAfter +
                          " with --aperture needs --horizons FILE (aal-bake --horizons)");
  }
  v.stats = o.stats;
  // Bad input fails here, before a window opens.
  std::shared_ptr<const aal::Heightfield> field = aal::loadViewerDem(o.dem, o.exaggeration);
  if (v.cameraPath) aal::requireCameraPathWithinReach(*v.cameraPath, o.cameraPath, *field);
  if (!o.aperture.empty()) {
    const aal::ApertureMapReader map(o.aperture);
    aal::checkApertureMatchesDem(map.header(), o.aperture, *field, o.dem);
  }
  if (!o.horizons.empty()) {
    v.horizons =
        std::make_shared<const aal::HorizonMap>(aal::readHorizonsOfDem(o.horizons, *field));
  }
  v.lighting = initialLighting(o, *field);
  aal::Viewer viewer(v, std::move(field));
  return viewer.run();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Flies over a DEM lit by the sun and the sky with ambient aperture lighting, in a "
      "window.\nWithout --aperture the aperture map comes from the cache shared with aal-render, "
      "or is baked in the background (baseline shading until it is ready).\nNo display? Use "
      "aal-render for headless images.",
      "aal-view");
  app.footer(kControls);
  Options o;
  std::string modes;
  for (const auto& [name, mode] : aal::toolShadingModes())
    modes += (modes.empty() ? "" : ", ") + name;
  app.add_option("dem", o.dem, "input DEM (any raster GDAL reads: GeoTIFF, VRT, .hgt, .asc, ...)")
      ->required();
  app.add_option("--aperture", o.aperture, "aperture map baked from this DEM by aal-bake");
  app.add_option("--size", o.size, "window size WIDTHxHEIGHT (screen coordinates)")
      ->capture_default_str();
  app.add_option("--horizons", o.horizons,
                 "directional horizons baked from this DEM by aal-bake --horizons: the panel "
                 "then offers the horizon mode (the sun through the horizon in its azimuth)");
  app.add_option("--mode", o.mode, "shading: " + modes + " (horizon needs --horizons)")
      ->check(CLI::IsMember(aal::toolShadingModes()))
      ->capture_default_str();
  aal::addSunOptions(
      app, o.sun,
      {.defaultSun = false, .placed = "--time, or the panel's date and time", .radius = false});
  app.add_option("--exaggeration", o.exaggeration,
                 "vertical exaggeration: heights times X (the aperture map is baked for it: "
                 "cached per exaggeration; a map given with --aperture must have been baked with "
                 "the same z scale)")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  app.add_option("--water-level", o.waterLevelM,
                 "paint terrain at or below this height (m) as water (default: no water)");
  app.add_option("--frames", o.frames,
                 "scripted run: render N frames (after the aperture map is ready), then exit");
  aal::addCameraPathOption(app, o.cameraPath,
                           "with --frames spread over the N frames, else played in real time");
  app.add_option("--screenshot", o.screenshot, "save the last scripted frame as this PNG");
  app.add_option("--timeout", o.timeoutS, "close the window after this many seconds")
      ->check(aal::kPositive);
  app.add_option("--drop", o.drop,
                 "after the first frame, open this DEM as if it were dropped on the window; "
                 "repeated, the DEMs as if dropped together (each read in turn, the last shown)")
      ->allow_extra_args(false);
  // Test hooks: what the user does to the window, scripted. FRAME counts
  // like --frames.
  app.add_option("--resize-after", o.resizeAfter,
                 "FRAME:WxH: resize the window after frame FRAME (tests, demos)");
  app.add_option("--minimise-after", o.minimiseAfter,
                 "FRAME: minimise the window after frame FRAME, restore it a few event-loop "
                 "iterations later (tests, demos; a window manager does the minimising)");
  app.add_option("--toggle-vsync-after", o.toggleVsyncAfter,
                 "FRAME: switch vsync after frame FRAME, as the panel does (tests, demos)");
  app.add_option("--mode-after", o.modeAfter,
                 "FRAME:MODE: switch the shading mode after frame FRAME, as the panel does "
                 "(tests, demos)");
  app.add_option("--sun-azimuth-after", o.sunAzimuthAfter,
                 "FRAME:DEG: after frame FRAME set the sun's azimuth (degrees clockwise from "
                 "north, the elevation kept), as the panel's direct sun does (tests, demos)");
  app.add_option("--sun-sweep", o.sunSweepDeg,
                 "DEG: after every scripted frame turn the sun's azimuth by DEG degrees, the "
                 "elevation kept, as the panel's direct sun does (benchmarks of the horizon "
                 "mode's re-lays)")
      ->check(CLI::Range(-90.0, 90.0));
  app.add_flag("--no-obscurance", o.noObscurance,
               "start with the obscurance pass off (the panel switches it)");
  app.add_flag("--no-vsync", o.noVsync, "present without waiting for vsync (MAILBOX/IMMEDIATE)");
  app.add_flag("--stats", o.stats, "print frame time, FPS and GPU time per pass at the end");
  aal::addGpuOptions(app, o.gpu, /*panel=*/true);
  app.add_option("--target-fps", o.targetFps,
                 "while the view changes, draw fewer pixels (down to half the width and height, "
                 "scaled up) to keep this frame rate; at rest every pixel. 0: off. Default 30, "
                 "off in scripted runs (--frames)")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--temporal", o.temporal,
                 "the frames drawn smaller: on, rebuilt at full resolution from the frames "
                 "before (jittered samples, the last frame reprojected); off, scaled up; auto, "
                 "on except on a CPU device, where rebuilding costs more than it saves "
                 "(docs/viewer.md)")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--azimuths", o.azimuths, "azimuths of a background bake")
      ->check(CLI::Range(4, 4096))
      ->capture_default_str();
  return aal::runTool(app, argc, argv, [&] { return run(o); });
}
