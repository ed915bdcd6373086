#include "aperture/tools/render/render_options.h"

#include <map>
#include <sstream>

#include "aperture/engine/supersampling.h"
#include "aperture/engine/terrain_tiles.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/reference/reference_renderer.h"
#include "aperture/tools/horizon_option.h"
#include "aperture/tools/options/output_options.h"

namespace aal {
namespace {

// The DEM, the maps baked from it, and where the images go.
void addInputOutputOptions(CLI::App& app, RenderOptions& o) {
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
}

// The CPU reference's rays and samples (--mode reference, --compare).
void addReferenceOptions(CLI::App& app, RenderOptions& o) {
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
      ->check(CLI::Range(1, kMaxReferenceSubpixels))
      ->capture_default_str();
}

// The surface's colour and its near-field obscurances.
void addSurfaceOptions(CLI::App& app, RenderOptions& o) {
  app.add_option("--albedo", o.albedo,
                 "surface colour image, e.g. an orthophoto (resampled to the DEM when its size "
                 "differs); default: a palette by height and slope");
  app.add_option("--albedo-value", o.albedoValue,
                 "constant surface albedo A or R,G,B in [0, 1] (instead of --albedo)");
  app.add_option("--obscurance-radius", o.obscuranceRadiusM,
                 "near-field radius R of the containment-test obscurances in metres (default: " +
                     std::to_string(int(kDefaultObscuranceRadiusCells)) +
                     " DEM cells, at most the DEM's shorter side)");
  app.add_option("--obscurance-samples", o.obscuranceSamples,
                 "obscurance sample count n: 8, 16 or 32")
      ->capture_default_str();
  app.add_option("--obscurance-steps", o.obscuranceSteps,
                 "obscurance test points per ray m: 1 or 2")
      ->capture_default_str();
  app.add_flag("--no-obscurance", o.noObscurance,
               "no obscurances: the ambient transfer W is 1 everywhere");
}

// The image, its camera, the sun, the air and what is drawn besides the DEM.
void addSceneOptions(CLI::App& app, RenderOptions& o) {
  app.add_option("--size", o.size, "image size WIDTHxHEIGHT")->capture_default_str();
  addCameraOptions(app, o.camera);
  addSunOptions(app, o.sun, {.placed = "--time or --time-range"});
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
}

// --mode: the GPU's shading modes and the CPU reference.
void addModeOption(CLI::App& app, RenderOptions& o) {
  const std::map<std::string, ShadingMode>& modes = toolShadingModes();
  std::string names;
  for (const auto& [name, mode] : modes) names += (names.empty() ? "" : ", ") + name;
  app.add_option("--mode", o.mode,
                 "shading: " + names + ", or " + kReferenceMode +
                     " (CPU ray tracer: sun-disk shadow rays, sky rays with one bounce; constant "
                     "albedo; slow, for measuring the others)")
      ->check(CLI::IsMember([&modes] {
        std::vector<std::string> choices{kReferenceMode};
        for (const auto& entry : modes) choices.push_back(entry.first);
        return choices;
      }()))
      ->capture_default_str();
}

// The DEM's units and exaggeration, and how the GPU draws it.
void addTerrainAndGpuOptions(CLI::App& app, RenderOptions& o) {
  addDemUnitsOptions(app, o.units);
  app.add_option("--exaggeration", o.exaggeration,
                 "vertical exaggeration: heights times X (the aperture map is baked for it: "
                 "cached per exaggeration; a map given with --aperture must have been baked with "
                 "the same z scale)")
      ->check(CLI::Range(0.01, 100.0))
      ->capture_default_str();
  addGpuOptions(app, o.gpu);
  app.add_option("--supersample", o.supersample,
                 "N x N shading points per pixel, averaged (linear radiance, then the tone map): "
                 "smooth edges, and less shimmer in --camera-path movies, for up to N^2 the "
                 "time and memory of a frame (docs/comparison.md, \"Shimmer in motion\"). "
                 "With --compare: the GPU modes' frames")
      ->check(CLI::Range(1u, kMaxSupersampling))
      ->capture_default_str();
  app.add_option("--max-tile", o.maxTileTexels,
                 "split the DEM's textures into tiles of at most N texels across, rounded down "
                 "to a multiple of 32 (tests; by default only DEMs beyond the device's largest "
                 "image are tiled)")
      ->check(CLI::Range(kTerrainMipAlignment, uint32_t(1) << 20));
}

// Image sequences: along a camera path, over a time range.
void addSequenceOptions(CLI::App& app, RenderOptions& o) {
  addCameraPathOption(
      app, o.cameraPath,
      "render an image sequence along it: --frames images spread from its first keyframe to its "
      "last, into OUT-0001.png ... (and OUT.mp4 with ffmpeg); with --compare, the pan along "
      "which the shimmer is measured");
  app.add_option("--time-range", o.timeRange,
                 "render an image sequence with the sun from START to END (UTC, ISO 8601), "
                 "--frames images, both ends included (a time-lapse)")
      ->expected(2);
  app.add_option("--frames", o.frames, "images in a --camera-path or --time-range sequence");
  app.add_option("--temporal", o.temporal,
                 "a sequence's frames: on, each pixel the mean of its points over the frames "
                 "before, moved with the camera (a still camera's points jittered within the "
                 "pixel): less shimmer, for about a tenth more a frame and 8 frames more at the "
                 "start; off, each frame on its own; "
                 "auto, on along a --camera-path (and the --compare pan), off for a "
                 "--time-range, whose moving sun the history would trail "
                 "(docs/rendering.md, \"Temporal reconstruction\")")
      ->check(CLI::IsMember({"auto", "on", "off"}))
      ->capture_default_str();
  app.add_option("--fps", o.fps, "frame rate of the sequence's MP4")
      ->check(CLI::Range(1.0, 240.0))
      ->capture_default_str();
}

}  // namespace

void addRenderOptions(CLI::App& app, RenderOptions& o) {
  addInputOutputOptions(app, o);
  addReferenceOptions(app, o);
  addSurfaceOptions(app, o);
  addSceneOptions(app, o);
  addModeOption(app, o);
  addTerrainAndGpuOptions(app, o);
  addSequenceOptions(app, o);
  app.add_flag("--stats", o.stats,
               "print per-pass GPU times (the device's timestamps) and the triangle count");
  app.add_option("--pass-profile", o.passProfile,
                 "N: after the image, draw it N times more with each pass submitted on its own "
                 "and waited for, and print each pass's median wall-clock and CPU time against "
                 "the frame's in one submission (a CPU device's timestamps cannot tell where "
                 "its time goes)")
      ->check(CLI::Range(1, 1000));
  addProgressOptions(app, o.report);
}

glm::vec3 parseAlbedoValue(const std::string& text, const std::string& option) {
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
    throw InputError(option + " must be A or R,G,B with values in [0, 1], got '" + text + "'");
  }
  return glm::vec3(v);
}

}  // namespace aal
