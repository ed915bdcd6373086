// aal-render: headless ambient aperture lighting of a DEM into an image.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/supersampling.h"
#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/preprocess/aperture_cache.h"
#include "aperture/preprocess/progress.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/albedo_image.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/reference/reference_renderer.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/terrain/view/camera_path.h"
#include "aperture/tools/horizon_option.h"
#include "aperture/tools/mode_comparison.h"
#include "aperture/tools/options/camera_options.h"
#include "aperture/tools/options/dem_units_options.h"
#include "aperture/tools/options/gpu_options.h"
#include "aperture/tools/options/output_options.h"
#include "aperture/tools/options/sun_options.h"
#include "aperture/tools/render_sequence.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace {

const std::map<std::string, aal::ShadingMode>& kModes = aal::toolShadingModes();

struct Options {
  std::string dem, aperture, output, albedo;
  // Directional horizons (aal-bake --horizons); --compare takes several.
  std::vector<std::string> horizons;
  std::string size = "1280x720";
  aal::CameraOptions camera;
  aal::SunOptions sun;
  double turbidity = aal::kDefaultTurbidity;
  std::optional<double> ev100;
  std::optional<double> visibilityKm;
  std::optional<double> waterLevelM;
  std::string mode = "approx";
  aal::DemUnitsOptions units;
  double exaggeration = 1.0;
  aal::GpuOptions gpu;
  uint32_t supersample = 1;
  uint32_t maxTileTexels = 0;
  bool stats = false;
  bool quiet = false;
  std::string albedoValue;
  std::optional<double> obscuranceRadiusM;
  int obscuranceSamples = aal::ObscuranceSettings{}.samples, obscuranceSteps = 1;
  bool noObscurance = false;
  std::string background = "sky";  // --background sky|transparent
  std::optional<double> baseDepthM;
  std::string baseColor = "0.35,0.3,0.25";
  std::string compare;  // folder for --compare
  // Image sequences: --camera-path and/or --time-range START END, --frames N.
  std::string cameraPath;
  std::vector<std::string> timeRange;
  std::optional<int> frames;
  double fps = 30;
  int referenceSunRays = aal::ComparisonOptions{}.sunRays;
  int referenceSkyRays = aal::ComparisonOptions{}.skyRays;
  int referenceSubpixels = aal::ComparisonOptions{}.subpixels;  // per axis
};

// The CPU ray tracer's name on --mode (not a GPU shading mode).
constexpr const char* kReferenceMode = "reference";

// --albedo-value, --base-color: one grey value or R,G,B, each in [0, 1].
glm::vec3 parseAlbedoValue(const std::string& text, const std::string& option = "--albedo-value") {
  std::istringstream in(text);
  glm::dvec3 v;
  char c1 = 0, c2 = 0;
  bool ok = static_cast<bool>(in >> v.x);
  if (ok && in.eof()) {
    v.y = v.z = v.x;
  } else {
    ok = ok && (in >> c1 >> v.y >> c2 >> v.z) && c1 == ',' && c2 == ',' && in.eof();
  }
  for (int c = 0; c < 3 && ok; ++c) ok = v[c] >= 0 && v[c] <= 1;
  if (!ok) {
    throw aal::InputError(option + " must be A or R,G,B with values in [0, 1], got '" + text + "'");
  }
  return glm::vec3(v);
}

// A sequence's checks and its time range, before any work; its camera path
// is read once the paths are checked (run).
struct Sequence {
  std::optional<aal::CameraPath> path;
  std::optional<aal::UtcTime> start, end;
  int frames = 0;
};
std::optional<Sequence> sequenceOf(const Options& o, bool reference) {
  const bool wanted = !o.cameraPath.empty() || !o.timeRange.empty();
  if (!wanted) {
    if (o.frames) throw aal::InputError("--frames needs --camera-path FILE or --time-range");
    return std::nullopt;
  }
  if (!o.frames) {
    throw aal::InputError("--camera-path and --time-range need --frames N (how many images)");
  }
  if (*o.frames < 1 || *o.frames > 1'000'000) {
    throw aal::InputError("--frames must be in [1, 1000000], got " + std::to_string(*o.frames));
  }
  // --compare takes a camera path as the pan its shimmer is measured along.
  if (reference || (!o.compare.empty() && !o.timeRange.empty())) {
    throw aal::InputError(std::string(reference ? "an image sequence (--camera-path, --time-range)"
                                                : "--time-range") +
                          " is for -o images of the GPU renderer, not " +
                          (reference ? "--mode reference" : "--compare"));
  }
  if (!o.compare.empty() && *o.frames < 3) {
    throw aal::InputError(
        "--compare with --camera-path measures the shimmer along it: give "
        "--frames 3 or more (a second difference in time needs three), got " +
        std::to_string(*o.frames));
  }
  Sequence s;
  s.frames = *o.frames;
  if (!o.cameraPath.empty()) {
    if (!o.camera.position.empty() || !o.camera.lookAt.empty()) {
      throw aal::InputError("--camera-path sets the camera: leave out --camera and --look-at");
    }
  }
  if (!o.timeRange.empty()) {
    if (!o.sun.time.empty() || o.sun.azimuthDeg) {
      throw aal::InputError(
          "--time-range sets the sun: leave out --time, --sun-azimuth and --sun-elevation");
    }
    s.start = aal::parseIso8601Utc(o.timeRange[0]);
    s.end = aal::parseIso8601Utc(o.timeRange[1]);
    for (int i = 0; i < 2; ++i) {
      if (!(i == 0 ? s.start : s.end)) {
        throw aal::InputError(
            "--time-range takes two ISO 8601 times, e.g. 2024-06-21T10:00Z, got '" +
            o.timeRange[i] + "'");
      }
    }
    if (!(aal::secondsBetween(*s.start, *s.end) > 0)) {
      throw aal::InputError("--time-range END (" + o.timeRange[1] + ") must come after START (" +
                            o.timeRange[0] + ")");
    }
  }
  return s;
}

aal::ComparisonOptions comparisonOptions(const Options& o,
                                         const std::optional<glm::vec3>& albedoValue) {
  aal::ComparisonOptions c;
  c.sunRays = o.referenceSunRays;
  c.skyRays = o.referenceSkyRays;
  c.subpixels = o.referenceSubpixels;
  c.albedo = albedoValue.value_or(glm::vec3(aal::kReferenceTerrainAlbedo));
  c.supersample = o.supersample;
  return c;
}

// --mode reference: the CPU ray tracer alone (no Vulkan device needed).
int renderReferenceImage(const Options& o, const aal::Heightfield& field,
                         const aal::FrameSettings& settings, uint32_t width, uint32_t height,
                         const std::optional<glm::vec3>& albedoValue) {
  const aal::ReferenceSettings r =
      aal::referenceSettingsFor(settings, width, height, comparisonOptions(o, albedoValue));
  aal::ProgressBar bar("ray tracing", !o.quiet);
  const auto start = std::chrono::steady_clock::now();
  const aal::ReferenceImage image =
      aal::renderReference(field, r, [&](double f) { bar.update(f); });
  bar.finish();
  aal::writeFrame(o.output, aal::referenceFrame(image, settings.lighting.exposure));
  if (!o.quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "aal-render: reference (%d sun + %d sky rays per pixel over %d x %d "
                 "subpixels) in %.1f s, wrote %s\n",
                 r.sunRays, r.skyRays, r.subpixels, r.subpixels, seconds, o.output.c_str());
  }
  return aal::kExitOk;
}

// The horizon modes --compare adds, one per --horizons file: "horizon", or
// with several "horizon-STEM" (numbered when a name is taken, so that no
// output is lost).
std::vector<std::string> horizonModeNames(const std::vector<std::string>& horizonPaths,
                                          const std::vector<aal::ComparedMode>& defaultModes) {
  std::vector<std::string> taken, names;
  for (const aal::ComparedMode& m : defaultModes) taken.push_back(m.name);
  for (size_t i = 0; i < horizonPaths.size(); ++i) {
    std::string name = horizonPaths.size() == 1
                           ? std::string("horizon")
                           : "horizon-" + std::filesystem::path(horizonPaths[i]).stem().string();
    for (const std::string& other : taken) {
      if (other == name) name.append("-").append(std::to_string(i + 1));
    }
    taken.push_back(name);
    names.push_back(name);
  }
  return names;
}

// The modes --compare renders, by name: comparisonFileNames gives its files.
std::vector<std::string> comparedModeNames(const Options& o) {
  aal::FrameSettings settings;
  settings.obscurance.enabled = !o.noObscurance;
  std::vector<std::string> names;
  const std::vector<aal::ComparedMode> modes = aal::defaultComparedModes(settings);
  for (const aal::ComparedMode& m : modes) names.push_back(m.name);
  for (const std::string& name : horizonModeNames(o.horizons, modes)) names.push_back(name);
  return names;
}

// The table of --compare on stdout: each mode's errors and, along a pan, its
// shimmer (kcd/m²) and the ratio to the reference's (whose row comes last).
void printComparison(const aal::Comparison& c) {
  const bool pan = c.referenceShimmer.has_value();
  std::printf("%-20s %14s %22s", "mode", "relative RMSE", "mean relative error");
  if (pan) std::printf(" %12s %12s", "shimmer", "x reference");
  std::printf("\n");
  const auto shimmer = [&](double s) {
    std::printf(" %12.5f %12.2f", s, *c.referenceShimmer > 0 ? s / *c.referenceShimmer : 0.0);
  };
  for (const aal::ModeError& e : c.modes) {
    std::printf("%-20s %13.2f%% %21.2f%%", e.mode.c_str(), 100 * e.relativeRmse,
                100 * e.meanRelativeError);
    if (pan) shimmer(e.shimmer.value_or(0));
    std::printf("\n");
  }
  if (pan) {
    std::printf("%-20s %14s %22s", "reference", "", "");
    shimmer(*c.referenceShimmer);
    std::printf("\n");
  }
}

// --compare FOLDER: every mode against the reference, a table on stdout.
// With several horizon maps, one horizon mode for each ("horizon-STEM"), the
// scene given each map before its rendering: one reference for all. With a
// camera path, the still images are its first frame's, and every mode and
// the reference are rendered along it for their shimmer.
int runComparison(const Options& o, const aal::Heightfield& field, aal::TerrainScene& scene,
                  aal::TerrainRenderer& renderer, aal::FrameSettings settings,
                  const std::optional<glm::vec3>& albedoValue, const aal::Device& device,
                  const std::vector<std::shared_ptr<const aal::HorizonMap>>& horizons,
                  const std::optional<Sequence>& pan) {
  std::vector<aal::Camera> cameras;
  if (pan && pan->path) {
    for (int i = 0; i < pan->frames; ++i) {
      cameras.push_back(pan->path->at(pan->path->frameTime(i, pan->frames)));
    }
    settings.camera = cameras.front();
  }
  aal::ProgressBar bar("ray tracing the reference", !o.quiet);
  std::vector<aal::ComparedMode> modes = aal::defaultComparedModes(settings);
  const std::vector<std::string> names = horizonModeNames(o.horizons, modes);
  for (size_t i = 0; i < horizons.size(); ++i) {
    aal::ComparedMode m{names[i], aal::ShadingMode::Horizon, settings.obscurance.enabled};
    if (horizons.size() > 1) {
      // Laid for the one sun (horizonPairFor): no re-lay in the frame.
      const int first = aal::horizonPairFor(horizons[i]->directions,
                                            aal::sunAzimuthRad(settings.lighting.sunDirection), -1);
      m.prepare = [&scene, &device, &horizons, i, first] {
        scene.setHorizons(device, horizons[i], first);
      };
    }
    modes.push_back(std::move(m));
  }
  aal::Comparison c =
      aal::compareModes(renderer, scene, field, settings, modes, comparisonOptions(o, albedoValue),
                        [&](double f) { bar.update(f); });
  bar.finish();
  if (!cameras.empty()) {
    aal::ProgressBar panBar("rendering the pan (" + std::to_string(cameras.size()) + " frames)",
                            !o.quiet);
    aal::measureShimmer(c, renderer, scene, field, settings, modes,
                        comparisonOptions(o, albedoValue), cameras,
                        [&](double f) { panBar.update(f); });
    panBar.finish();
  }
  aal::writeComparison(o.compare, c, settings.lighting.exposure);
  printComparison(c);
  if (!o.quiet) {
    std::fprintf(stderr, "aal-render: reference in %.1f s; wrote %s/\n", c.referenceSeconds,
                 o.compare.c_str());
  }
  return aal::kExitOk;
}

// Frame i of a sequence: the camera along the path, the sun at the frame's
// time.
void setSequenceFrame(const Options& o, const Sequence& seq, const aal::Heightfield& field, int i,
                      aal::FrameSettings& settings) {
  if (seq.path) settings.camera = seq.path->at(seq.path->frameTime(i, seq.frames));
  if (seq.start) {
    const aal::GeoPlace place = aal::defaultSunPlace(field);
    const double lat = o.sun.latitudeDeg.value_or(place.latitudeDeg),
                 lon = o.sun.longitudeDeg.value_or(place.longitudeDeg);
    const aal::UtcTime t = aal::sequenceTime(*seq.start, *seq.end, i, seq.frames);
    const aal::SolarPosition sun = aal::solarPosition(t, lat, lon);
    aal::setSunAndSky(settings.lighting, sun.azimuthDeg, sun.elevationDeg, o.turbidity,
                      sun.sunDistanceAu);
  }
}

// A frame of -o at the output's size: with --supersample N rendered at N
// times the width and height (the renderer's size) and averaged down
// (engine/supersampling.h); an explicit --lod-error stays in output pixels.
aal::FrameResult renderOutputFrame(const Options& o, const aal::TerrainScene& scene,
                                   aal::TerrainRenderer& renderer,
                                   const aal::FrameSettings& settings) {
  return aal::renderSupersampled(renderer, scene, settings, o.supersample,
                                 aal::wantsLinearOutput(o.output));
}

// The MP4 a sequence of PNG frames makes with ffmpeg: OUT.mp4 (none for
// EXR frames).
std::string moviePath(const Options& o) {
  if (aal::wantsLinearOutput(o.output)) return {};
  return std::filesystem::path(o.output).replace_extension(".mp4").string();
}

// --camera-path / --time-range: frames OUT-0001.ext ... and, for PNG frames
// with ffmpeg installed, OUT.mp4 (docs/rendering.md). The renderer re-lays
// the horizons when a frame's sun needs it (TerrainRenderer::record).
int renderSequence(const Options& o, const Sequence& seq, const aal::Heightfield& field,
                   const aal::TerrainScene& scene, aal::TerrainRenderer& renderer,
                   aal::FrameSettings settings) {
  aal::ProgressBar bar("rendering " + std::to_string(seq.frames) + " frames", !o.quiet);
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < seq.frames; ++i) {
    setSequenceFrame(o, seq, field, i, settings);
    aal::throwIfInterrupted();
    const aal::FrameResult frame = renderOutputFrame(o, scene, renderer, settings);
    aal::writeFrame(aal::sequenceFramePath(o.output, i, seq.frames), frame);
    bar.update(double(i + 1) / seq.frames);
  }
  bar.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string first = aal::sequenceFramePath(o.output, 0, seq.frames),
                    last = aal::sequenceFramePath(o.output, seq.frames - 1, seq.frames);
  if (!o.quiet) {
    std::fprintf(stderr, "aal-render: %d frames in %.1f s (%.0f ms each): %s .. %s\n", seq.frames,
                 seconds, 1e3 * seconds / seq.frames, first.c_str(), last.c_str());
  }
  if (aal::wantsLinearOutput(o.output)) return aal::kExitOk;  // EXR frames: no movie
  const std::optional<std::string> ffmpeg = aal::findFfmpeg();
  const std::string mp4 = moviePath(o);
  if (!ffmpeg) {
    if (!o.quiet) {
      std::fprintf(stderr, "aal-render: ffmpeg not found (Debian: apt-get install ffmpeg): no %s\n",
                   mp4.c_str());
    }
    return aal::kExitOk;
  }
  aal::encodeMp4(*ffmpeg, aal::sequencePattern(o.output, seq.frames), o.fps, mp4);
  if (!o.quiet) std::fprintf(stderr, "aal-render: wrote %s\n", mp4.c_str());
  return aal::kExitOk;
}

// The frames of a sequence of `count`, OUT-0001.png ..., by name in -o's
// folder.
aal::OutputFamily frameFiles(const std::string& output, int count) {
  const std::string folder = std::filesystem::path(output).parent_path().string();
  const auto name = [&](int i) {
    return std::filesystem::path(aal::sequenceFramePath(output, i, count)).filename().string();
  };
  return {"-o", output, folder.empty() ? "." : folder,
          "the frames " + name(0) + (count > 1 ? " .. " + name(count - 1) : ""),
          [output, count](const std::string& file) {
            return aal::isSequenceFrameName(output, count, file);
          }};
}

// requireWritableOutput for a file in `folder`, which writeComparison
// creates with its parents when missing: the nearest folder that exists
// must take it.
void requireWritableComparison(const std::string& folder, const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(folder, error) && !fs::is_directory(folder, error)) {
    throw aal::InputError("--compare " + folder +
                          " is a file: --compare names a folder for its images; give a folder");
  }
  fs::path missing = fs::absolute(folder, error) / file;
  while (missing.has_parent_path() && missing.parent_path() != missing.root_path() &&
         !fs::exists(missing.parent_path(), error)) {
    missing = missing.parent_path();
  }
  aal::requireWritableOutput(missing.string());
}

// Every path the run writes against every file it reads, before any work:
// -o, or a sequence's frames and its movie, or the files of --compare; the
// DEM with the files GDAL reads for it (a VRT's sources), a tiled aperture
// map's files (docs/dem-input.md, "Outputs").
void checkPaths(const Options& o, const std::optional<Sequence>& sequence) {
  aal::NamedPaths inputs = aal::inputFiles("DEM", o.dem, /*raster=*/true);
  aal::append(inputs, aal::inputFiles("--aperture", o.aperture));
  inputs.push_back({"--albedo", o.albedo});
  inputs.push_back({"--camera-path", o.cameraPath});
  for (const std::string& path : o.horizons) inputs.push_back({"--horizons", path});
  aal::NamedPaths outputs;
  std::vector<aal::OutputFamily> families;
  if (!o.compare.empty()) {
    for (const std::string& name : aal::comparisonFileNames(comparedModeNames(o))) {
      outputs.push_back({"--compare", (std::filesystem::path(o.compare) / name).string(),
                         "written by --compare " + o.compare});
    }
  } else {
    outputs.push_back({"-o", o.output});
    if (sequence) {
      families.push_back(frameFiles(o.output, sequence->frames));
      // ffmpeg writes it only when installed (renderSequence).
      if (const std::string mp4 = moviePath(o); !mp4.empty() && aal::findFfmpeg()) {
        outputs.push_back({"-o", mp4, "the movie of the frames"});
      }
    }
  }
  aal::checkDistinctFiles(inputs, outputs, families);
  for (const aal::RunPath& out : outputs) {
    if (out.option == "--compare") {
      requireWritableComparison(o.compare, std::filesystem::path(out.path).filename().string());
    } else {
      aal::requireWritableOutput(out.path);
    }
  }
  for (const aal::OutputFamily& frames : families) {
    aal::requireWritableFamily(
        frames, std::filesystem::path(aal::sequenceFramePath(o.output, 0, sequence->frames))
                    .filename()
                    .string());
  }
}

int run(const Options& o) {
  const bool reference = o.mode == kReferenceMode;
  const aal::ShadingMode mode = reference ? aal::ShadingMode::Approx : kModes.at(o.mode);
  const auto [width, height] = aal::parseSize(o.size);
  if (o.output.empty() == o.compare.empty()) {
    throw aal::InputError("give -o IMAGE or --compare FOLDER (one of them)");
  }
  if ((reference || !o.compare.empty()) && !o.albedo.empty()) {
    throw aal::InputError(
        "the reference renderer knows only a constant albedo: use --albedo-value, not --albedo");
  }
  if (reference && o.supersample > 1) {
    throw aal::InputError(
        "--supersample is for the GPU's modes: the reference takes --reference-subpixels");
  }
  if (reference && !o.compare.empty()) {
    throw aal::InputError("--compare renders the reference itself: leave out --mode reference");
  }
  if (o.horizons.size() > 1 && o.compare.empty()) {
    throw aal::InputError("--horizons given " + std::to_string(o.horizons.size()) +
                          " times: only --compare takes several");
  }
  if (mode == aal::ShadingMode::Horizon && o.horizons.empty()) {
    throw aal::InputError("--mode horizon needs --horizons FILE (aal-bake --horizons)");
  }
  if (!o.output.empty()) {
    if (!aal::isSupportedImageOutput(o.output)) {
      throw aal::InputError("output " + o.output + " must end in .png or .exr");
    }
    aal::requireWritableOutput(o.output);
  }
  if (o.baseDepthM && (reference || !o.compare.empty())) {
    throw aal::InputError("--base is drawn by the GPU renderer into -o images, not " +
                          std::string(reference ? "--mode reference" : "--compare"));
  }
  const glm::vec3 baseAlbedo = parseAlbedoValue(o.baseColor, "--base-color");
  if (o.background == "transparent" && (reference || !o.compare.empty())) {
    throw aal::InputError("--background transparent is for -o images of the GPU renderer, not " +
                          std::string(reference ? "--mode reference" : "--compare"));
  }
  if (o.sun.azimuthDeg.has_value() != o.sun.elevationDeg.has_value()) {
    throw aal::InputError("give --sun-azimuth and --sun-elevation together");
  }
  // As aal-relief: a place without a time would be ignored.
  if (o.sun.time.empty() && o.timeRange.empty() && (o.sun.latitudeDeg || o.sun.longitudeDeg)) {
    throw aal::InputError(
        "--lat and --lon place the sun for --time (or --time-range); give --time too");
  }
  std::optional<Sequence> sequence = sequenceOf(o, reference);
  checkPaths(o, sequence);
  // Read once the paths are known to be apart.
  if (sequence && !o.cameraPath.empty()) sequence->path = aal::CameraPath::load(o.cameraPath);

  if (!o.albedo.empty() && !o.albedoValue.empty()) {
    throw aal::InputError("give --albedo or --albedo-value, not both");
  }
  const std::optional<glm::vec3> albedoValue =
      o.albedoValue.empty() ? std::nullopt : std::optional(parseAlbedoValue(o.albedoValue));

  aal::DemLoadOptions load;
  aal::applyDemUnits(o.units, load);
  load.exaggeration = o.exaggeration;
  load.peakBytesPerTexel =
      reference ? aal::kReferenceRenderBytesPerTexel : aal::kRenderBytesPerTexel;
  load.workName = reference ? "a ray-traced render" : "a render";
  load.memoryHint =
      "cut the DEM (`gdal_translate -srcwin`) or coarsen it (`gdal_translate -outsize 50% 50%`)";
  const aal::Heightfield field = aal::loadDem(o.dem, load);
  aal::requireRenderableDem(field);
  const aal::ObscuranceSettings obscurance = aal::obscuranceFromOptions(
      !o.noObscurance, o.obscuranceSamples, o.obscuranceSteps, o.obscuranceRadiusM, field);
  // The camera's points against the DEM's extent, before the bake.
  std::optional<glm::dvec3> camera, lookAt;
  if (!o.camera.position.empty()) {
    camera = aal::parseTriple("--camera", o.camera.position);
    aal::requireWithinCameraReach("--camera " + o.camera.position, *camera, field);
  }
  if (!o.camera.lookAt.empty()) {
    lookAt = aal::parseTriple("--look-at", o.camera.lookAt);
    aal::requireWithinCameraReach("--look-at " + o.camera.lookAt, *lookAt, field);
  }
  if (sequence && sequence->path) {
    aal::requireCameraPathWithinReach(*sequence->path, o.cameraPath, field);
  }
  // The aperture map is streamed from its file into the GPU when the scene
  // is built, so it never sits in host memory as floats.
  std::string aperturePath = o.aperture;
  aal::ApertureMap inMemory;
  if (reference) {
    // The ray tracer needs no aperture map.
  } else if (!aperturePath.empty()) {
    const aal::ApertureMapReader check(aperturePath);
    aal::checkApertureMatchesDem(check.header(), aperturePath, field, o.dem);
  } else {
    std::vector<std::string> inputs = {o.albedo, o.cameraPath};
    inputs.insert(inputs.end(), o.horizons.begin(), o.horizons.end());
    aal::CachedAperture cached =
        aal::cachedOrBakedAperture(field, o.dem, aal::BakeOptions{}, o.quiet, inputs);
    aperturePath = cached.path.string();
    inMemory = std::move(cached.map);
  }

  std::optional<aal::AlbedoImage> albedo;
  if (!o.albedo.empty()) {
    albedo = aal::loadAlbedoImage(o.albedo, field.width, field.height, [&](const std::string& m) {
      if (!o.quiet) std::fprintf(stderr, "note: %s\n", m.c_str());
    });
  }
  // A --time-range sets the sun of every frame itself.
  const aal::SolarPosition sun =
      sequence && sequence->start ? aal::SolarPosition{} : aal::sunOf(o.sun, field);
  aal::FrameSettings settings;
  settings.mode = mode;
  settings.obscurance = obscurance;
  settings.albedoValue = albedoValue;
  const double aspect = double(width) / double(height);
  // Framed for the field of view asked for (docs/rendering.md, "Default camera").
  const double baseDepthM = o.baseDepthM.value_or(0.0) * o.exaggeration;
  settings.camera = aal::defaultCamera(field, aspect, o.camera.fovDeg, baseDepthM);
  if (camera) settings.camera.position = *camera;
  if (lookAt) settings.camera.lookAt = *lookAt;
  aal::requireCameraDirection(settings.camera.position, settings.camera.lookAt);
  settings.camera.verticalFovDeg = o.camera.fovDeg;
  settings.lod.maxErrorPixels = o.gpu.lodErrorPixels;
  settings.anisotropy = o.gpu.anisotropy;
  settings.transparentBackground = o.background == "transparent";
  // The depth is in the DEM's metres, like the heights before --exaggeration.
  if (o.baseDepthM) settings.base = aal::FrameSettings::Base{float(baseDepthM), baseAlbedo};
  aal::Lighting& light = settings.lighting;
  light =
      aal::defaultLighting(field, sun.azimuthDeg, sun.elevationDeg, o.turbidity, sun.sunDistanceAu);
  light.sunRadiusRad = static_cast<float>(aal::radians(o.sun.radiusDeg));
  if (o.visibilityKm) {
    light.hazeDensityPerM =
        static_cast<float>(aal::hazeDensityForVisibility(*o.visibilityKm * 1000));
  }
  if (o.ev100) light.exposure = aal::exposureFromEv100(static_cast<float>(*o.ev100));
  // The level is in the DEM's metres; the drawn heights are exaggerated.
  if (o.waterLevelM) settings.waterLevelM = static_cast<float>(*o.waterLevelM * o.exaggeration);

  if (reference) return renderReferenceImage(o, field, settings, width, height, albedoValue);

  aal::Instance instance;
  aal::Device device(instance, o.gpu.device);
  const uint32_t largest = device.properties().limits.maxImageDimension2D;
  if (width > largest || height > largest) {
    throw aal::InputError("--size " + o.size + " exceeds the device's largest image (" +
                          std::to_string(largest) + ")");
  }
  if (uint64_t(width) * o.supersample > largest || uint64_t(height) * o.supersample > largest) {
    throw aal::InputError(
        "--size " + o.size + " with --supersample " + std::to_string(o.supersample) + " renders " +
        std::to_string(uint64_t(width) * o.supersample) + "x" +
        std::to_string(uint64_t(height) * o.supersample) + ", beyond the device's largest image (" +
        std::to_string(largest) + "): a smaller --size or --supersample");
  }
  if (o.maxTileTexels > 0) {
    // A forced tile size that needs more texture pages than the renderer
    // binds is a bad argument, not a failure of the run.
    try {
      aal::planTerrainTiles(static_cast<uint32_t>(field.width), static_cast<uint32_t>(field.height),
                            aal::deviceTileLimits(device, aal::TerrainTiling{o.maxTileTexels, 0}));
    } catch (const std::runtime_error& e) {
      throw aal::InputError("--max-tile " + std::to_string(o.maxTileTexels) + ": " + e.what());
    }
  }
  std::unique_ptr<aal::TerrainScene> scene;
  if (aperturePath.empty()) {
    scene = std::make_unique<aal::TerrainScene>(device, field, inMemory,
                                                albedo ? &*albedo : nullptr, o.gpu.triangleBudget,
                                                aal::TerrainTiling{o.maxTileTexels, 0});
  } else {
    aal::ApertureMapReader reader(aperturePath);
    scene = std::make_unique<aal::TerrainScene>(device, field, reader, albedo ? &*albedo : nullptr,
                                                o.gpu.triangleBudget,
                                                aal::TerrainTiling{o.maxTileTexels, 0});
  }
  inMemory = {};
  albedo.reset();
  // The horizons of the two directions beside the first frame's sun on the
  // device (horizonPairFor): no re-lay before it. A sequence's later suns
  // re-lay when they leave that pair.
  aal::FrameSettings first = settings;
  if (sequence) setSequenceFrame(o, *sequence, field, 0, first);
  const float firstAzimuth = aal::sunAzimuthRad(first.lighting.sunDirection);
  std::vector<std::shared_ptr<const aal::HorizonMap>> horizonMaps;
  for (const std::string& path : o.horizons) {
    auto horizons = std::make_shared<const aal::HorizonMap>(aal::readHorizonsOfDem(path, field));
    try {
      scene->setHorizons(device, horizons,
                         aal::horizonPairFor(horizons->directions, firstAzimuth, -1));
    } catch (const std::invalid_argument& e) {
      throw aal::InputError(std::string("--horizons: ") + e.what());
    }
    horizonMaps.push_back(std::move(horizons));
  }
  aal::TerrainRenderer renderer(device, width * o.supersample, height * o.supersample);
  if (!o.compare.empty()) {
    return runComparison(o, field, *scene, renderer, settings, albedoValue, device, horizonMaps,
                         sequence);
  }
  if (sequence) return renderSequence(o, *sequence, field, *scene, renderer, settings);
  const aal::FrameResult frame = renderOutputFrame(o, *scene, renderer, settings);
  aal::writeFrame(o.output, frame);

  if (o.stats) {
    std::printf("device     %s\n", device.name().c_str());
    std::printf("size       %ux%u\n", width, height);
    std::printf("triangles  %zu\n", frame.triangles);
    std::printf("textures   %s, %.1f MiB\n", aal::describeTerrainTiles(scene->tiles()).c_str(),
                double(scene->textureBytes()) / (1 << 20));
    if (scene->hasHorizons()) {
      std::printf("horizons   %.1f MiB of them (moments of two directions)\n",
                  double(scene->horizonBytes()) / (1 << 20));
    }
    std::printf("sun        azimuth %.2f deg, elevation %.2f deg\n", sun.azimuthDeg,
                sun.elevationDeg);
    if (obscurance.enabled) {
      std::printf("obscurance R %.1f m, n %d, m %d\n", obscurance.radiusM, obscurance.samples,
                  obscurance.steps);
    } else {
      std::printf("obscurance off\n");
    }
    double total = 0;
    for (const auto& [pass, ms] : frame.passMilliseconds) {
      std::printf("gpu %-10s %8.3f ms\n", pass.c_str(), ms);
      total += ms;
    }
    std::printf("gpu total      %8.3f ms\n", total);
  }
  if (!o.quiet) std::fprintf(stderr, "aal-render: wrote %s\n", o.output.c_str());
  return aal::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Renders a DEM lit by the sun and the sky with ambient aperture lighting (headless).\n"
      "Without --aperture, the aperture map is baked once and cached (see aal-bake).",
      "aal-render");
  Options o;
  std::string modes;
  for (const auto& [name, mode] : kModes) modes += (modes.empty() ? "" : ", ") + name;
  app.add_option("dem", o.dem, "input DEM")->required();
  app.add_option("--aperture", o.aperture, "aperture map baked from this DEM by aal-bake");
  app.add_option("--horizons", o.horizons,
                 "directional horizons baked from this DEM by aal-bake --horizons: for --mode "
                 "horizon, and --compare adds that mode (given several times, --compare adds "
                 "one horizon-STEM mode for each file)")
      ->allow_extra_args(false);
  app.add_option("-o,--output", o.output, "output image: .png (display) or .exr (linear HDR)");
  app.add_option("--compare", o.compare,
                 "instead of -o: render every shading mode and the CPU reference into this "
                 "folder (images, error maps, errors.csv) and print each mode's error against "
                 "the reference (relative RMSE of linear radiance over the terrain). With "
                 "--camera-path and --frames N (3 or more): the images are the path's first "
                 "frame, and every mode and the reference are also rendered along the path for "
                 "their shimmer, the mean |Y(t+1) - 2 Y(t) + Y(t-1)| of linear luminance over "
                 "the terrain (columns shimmer and shimmer_vs_reference, and a reference row, "
                 "in errors.csv)");
  app.add_option("--reference-sun-rays", o.referenceSunRays,
                 "reference: shadow rays per pixel towards the sun's disk")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  app.add_option("--reference-sky-rays", o.referenceSkyRays,
                 "reference: cosine-weighted sky rays per pixel (one bounce where they hit)")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  app.add_option("--reference-subpixels", o.referenceSubpixels,
                 "reference: N x N point samples per pixel, averaged (the pixel's footprint, "
                 "as the GPU's mip levels prefilter it); they share the pixel's sun and sky "
                 "rays. 1: the one point through the pixel's centre")
      ->check(CLI::Range(1, aal::kMaxReferenceSubpixels))
      ->capture_default_str();
  app.add_option("--albedo", o.albedo,
                 "surface colour image, e.g. an orthophoto (resampled to the DEM when its size "
                 "differs); default: a palette by height and slope");
  app.add_option("--albedo-value", o.albedoValue,
                 "constant surface albedo A or R,G,B in [0, 1] (instead of --albedo)");
  app.add_option("--obscurance-radius", o.obscuranceRadiusM,
                 "near-field radius R of the containment-test obscurances in metres (default: " +
                     std::to_string(int(aal::kDefaultObscuranceRadiusCells)) +
                     " DEM cells, at most the DEM's shorter side)");
  app.add_option("--obscurance-samples", o.obscuranceSamples,
                 "obscurance sample count n: 8, 16 or 32")
      ->capture_default_str();
  app.add_option("--obscurance-steps", o.obscuranceSteps,
                 "obscurance test points per ray m: 1 or 2")
      ->capture_default_str();
  app.add_flag("--no-obscurance", o.noObscurance,
               "no obscurances: the ambient transfer W is 1 everywhere");
  app.add_option("--size", o.size, "image size WIDTHxHEIGHT")->capture_default_str();
  aal::addCameraOptions(app, o.camera);
  aal::addSunOptions(app, o.sun, {.placed = "--time or --time-range"});
  app.add_option("--turbidity", o.turbidity, "atmospheric turbidity (2 very clear .. 10 hazy)")
      ->check(CLI::Range(2.0, 10.0))
      ->capture_default_str();
  app.add_option("--ev", o.ev100, "exposure value at ISO 100 (default: automatic)");
  app.add_option("--visibility", o.visibilityKm,
                 "distance haze: visibility in km (default: 20 DEM diagonals, at least 200)")
      ->check(CLI::Range(0.1, 1e6));
  app.add_option("--background", o.background,
                 "what pixels without terrain show: sky, or transparent (alpha 0 in the PNG or "
                 "EXR; their colour stays the sky's)")
      ->check(CLI::IsMember({"sky", "transparent"}))
      ->capture_default_str();
  app.add_option("--base", o.baseDepthM,
                 "draw a solid base under the DEM: side walls from its edge down to DEPTH metres "
                 "below its lowest point, and a bottom")
      ->check(CLI::Range(0.001, 1e6));
  app.add_option("--base-color", o.baseColor, "albedo of the base: A or R,G,B in [0, 1]")
      ->capture_default_str();
  app.add_option("--water-level", o.waterLevelM,
                 "paint terrain at or below this height (m) as water (default: no water)");
  app.add_option("--mode", o.mode,
                 "shading: " + modes + ", or " + kReferenceMode +
                     " (CPU ray tracer: sun-disk shadow rays, sky rays with one bounce; constant "
                     "albedo; slow, for measuring the others)")
      ->check(CLI::IsMember([] {
        std::vector<std::string> names{kReferenceMode};
        for (const auto& entry : kModes) names.push_back(entry.first);
        return names;
      }()))
      ->capture_default_str();
  aal::addDemUnitsOptions(app, o.units);
  app.add_option("--exaggeration", o.exaggeration,
                 "vertical exaggeration: heights times X (the aperture map is baked for it: "
                 "cached per exaggeration; a map given with --aperture must have been baked with "
                 "the same z scale)")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  aal::addGpuOptions(app, o.gpu);
  app.add_option("--supersample", o.supersample,
                 "N x N shading points per pixel, averaged (linear radiance, then the tone map): "
                 "smooth edges, and less shimmer in --camera-path movies, for up to N^2 the "
                 "time and memory of a frame (docs/comparison.md, \"Shimmer in motion\"). "
                 "With --compare: the GPU modes' frames")
      ->check(CLI::Range(1u, aal::kMaxSupersampling))
      ->capture_default_str();
  app.add_option("--max-tile", o.maxTileTexels,
                 "split the DEM's textures into tiles of at most N texels across, rounded down "
                 "to a multiple of 32 (tests; by default only DEMs beyond the device's largest "
                 "image are tiled)")
      ->check(CLI::Range(aal::kTerrainMipAlignment, uint32_t(1) << 20));
  aal::addCameraPathOption(
      app, o.cameraPath,
      "render an image sequence along it: --frames images spread from its first keyframe to its "
      "last, into OUT-0001.png ... (and OUT.mp4 with ffmpeg); with --compare, the pan along "
      "which the shimmer is measured");
  app.add_option("--time-range", o.timeRange,
                 "render an image sequence with the sun from START to END (UTC, ISO 8601), "
                 "--frames images, both ends included (a time-lapse)")
      ->expected(2);
  app.add_option("--frames", o.frames, "images in a --camera-path or --time-range sequence");
  app.add_option("--fps", o.fps, "frame rate of the sequence's MP4")
      ->check(CLI::Range(1.0, 240.0))
      ->capture_default_str();
  app.add_flag("--stats", o.stats, "print per-pass GPU times and the triangle count");
  aal::addQuietFlag(app, o.quiet);
  return aal::runTool(app, argc, argv, [&] { return run(o); });
}
