// aal-render: headless ambient aperture lighting of a DEM into an image.
// The command line is tools/render/render_options.h; a run checks it
// (render_request.h), loads the DEM, sets the frame and renders it with the
// CPU reference (reference_image.h) or on the GPU (render_scene.h): -o's
// image (still_image.h), a sequence (image_sequence.h) or --compare
// (comparison_run.h).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/terrain/io/albedo_image.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/light/lighting.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/units.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/tools/render/comparison_run.h"
#include "aperture/tools/render/image_sequence.h"
#include "aperture/tools/render/reference_image.h"
#include "aperture/tools/render/render_options.h"
#include "aperture/tools/render/render_request.h"
#include "aperture/tools/render/render_scene.h"
#include "aperture/tools/render/still_image.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"

namespace {

aal::Heightfield loadRenderDem(const aal::RenderOptions& o, bool reference) {
  aal::DemLoadOptions load;
  aal::applyDemUnits(o.units, load);
  load.exaggeration = o.exaggeration;
  load.peakBytesPerTexel =
      reference ? aal::kReferenceRenderBytesPerTexel : aal::kRenderBytesPerTexel;
  load.workName = reference ? "a ray-traced render" : "a render";
  load.memoryHint =
      "cut the DEM (`gdal_translate -srcwin`) or coarsen it (`gdal_translate -outsize 50% 50%`)";
  aal::Heightfield field = aal::loadDem(o.dem, load);
  aal::requireRenderableDem(field);
  return field;
}

// --camera and --look-at, each when given.
struct CameraPoints {
  std::optional<glm::dvec3> position, lookAt;
};

// The camera's points against the DEM's extent, before the bake.
CameraPoints cameraPointsWithinReach(const aal::RenderOptions& o,
                                     const std::optional<aal::ImageSequence>& sequence,
                                     const aal::Heightfield& field) {
  CameraPoints points;
  if (!o.camera.position.empty()) {
    points.position = aal::parseTriple("--camera", o.camera.position);
    aal::requireWithinCameraReach("--camera " + o.camera.position, *points.position, field);
  }
  if (!o.camera.lookAt.empty()) {
    points.lookAt = aal::parseTriple("--look-at", o.camera.lookAt);
    aal::requireWithinCameraReach("--look-at " + o.camera.lookAt, *points.lookAt, field);
  }
  if (sequence && sequence->path) {
    aal::requireCameraPathWithinReach(*sequence->path, o.cameraPath, field);
  }
  return points;
}

std::optional<aal::AlbedoImage> loadAlbedo(const aal::RenderOptions& o,
                                           const aal::Heightfield& field) {
  if (o.albedo.empty()) return std::nullopt;
  return aal::loadAlbedoImage(o.albedo, field.width, field.height, [&](const std::string& m) {
    if (!o.report.quiet) std::fprintf(stderr, "note: %s\n", m.c_str());
  });
}

// The sun and sky of `sun`, with the options' disk, haze and exposure.
aal::Lighting lightingOf(const aal::RenderOptions& o, const aal::Heightfield& field,
                         const aal::SolarPosition& sun) {
  aal::Lighting light =
      aal::defaultLighting(field, sun.azimuthDeg, sun.elevationDeg, o.turbidity, sun.sunDistanceAu);
  light.sunRadiusRad = static_cast<float>(aal::radians(o.sun.radiusDeg));
  if (o.visibilityKm) {
    light.hazeDensityPerM =
        static_cast<float>(aal::hazeDensityForVisibility(*o.visibilityKm * 1000));
  }
  if (o.ev100) light.exposure = aal::exposureFromEv100(static_cast<float>(*o.ev100));
  return light;
}

// The frame the options describe (a sequence's first frame before
// setSequenceFrame).
aal::FrameSettings frameSettings(const aal::RenderOptions& o, const aal::RenderRequest& r,
                                 const aal::Heightfield& field,
                                 const aal::ObscuranceSettings& obscurance,
                                 const CameraPoints& points, const aal::SolarPosition& sun) {
  aal::FrameSettings settings;
  settings.mode = r.mode;
  settings.obscurance = obscurance;
  settings.albedoValue = r.albedoValue;
  const double aspect = double(r.width) / double(r.height);
  // Framed for the field of view asked for (docs/rendering.md, "Default camera").
  const double baseDepthM = o.baseDepthM.value_or(0.0) * o.exaggeration;
  settings.camera = aal::defaultCamera(field, aspect, o.camera.fovDeg, baseDepthM);
  if (points.position) settings.camera.position = *points.position;
  if (points.lookAt) settings.camera.lookAt = *points.lookAt;
  aal::requireCameraDirection(settings.camera.position, settings.camera.lookAt);
  settings.camera.verticalFovDeg = o.camera.fovDeg;
  settings.lod.maxErrorPixels = o.gpu.lodErrorPixels;
  settings.anisotropy = o.gpu.anisotropy;
  settings.transparentBackground = o.background == "transparent";
  // The depth is in the DEM's metres, like the heights before --exaggeration.
  if (o.baseDepthM) settings.base = aal::FrameSettings::Base{float(baseDepthM), r.baseAlbedo};
  settings.lighting = lightingOf(o, field, sun);
  // The level is in the DEM's metres; the drawn heights are exaggerated.
  if (o.waterLevelM) settings.waterLevelM = static_cast<float>(*o.waterLevelM * o.exaggeration);
  return settings;
}

int run(const aal::RenderOptions& o) {
  const aal::RenderRequest r = aal::checkedRequest(o);
  const aal::Heightfield field = loadRenderDem(o, r.reference);
  const aal::ObscuranceSettings obscurance = aal::obscuranceFromOptions(
      !o.noObscurance, o.obscuranceSamples, o.obscuranceSteps, o.obscuranceRadiusM, field);
  const CameraPoints points = cameraPointsWithinReach(o, r.sequence, field);
  aal::ApertureSource aperture = aal::apertureSource(o, field, r.reference);
  std::optional<aal::AlbedoImage> albedo = loadAlbedo(o, field);
  // A --time-range sets the sun of every frame itself.
  const aal::SolarPosition sun =
      r.sequence && r.sequence->start ? aal::SolarPosition{} : aal::sunOf(o.sun, field);
  const aal::FrameSettings settings = frameSettings(o, r, field, obscurance, points, sun);
  if (r.reference) {
    return aal::renderReferenceImage(o, field, settings, r.width, r.height, r.albedoValue);
  }

  aal::Instance instance;
  aal::Device device(instance, o.gpu.device);
  aal::checkDeviceLimits(o, device, r.width, r.height, field);
  const std::unique_ptr<aal::TerrainScene> scene =
      aal::buildScene(o, device, field, std::move(aperture), std::move(albedo));
  const std::vector<std::shared_ptr<const aal::HorizonMap>> horizonMaps =
      aal::loadHorizonMaps(o, r.sequence, field, settings, device, *scene);
  aal::TerrainRenderer renderer(device, r.width * o.supersample, r.height * o.supersample);
  if (!o.compare.empty()) {
    return aal::runComparison(o, field, *scene, renderer, settings, r.albedoValue, device,
                              horizonMaps, r.sequence);
  }
  if (r.sequence) return aal::renderSequence(o, *r.sequence, field, *scene, renderer, settings);
  return aal::renderStillImage(o, device, *scene, renderer, settings, r.width, r.height, sun);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Renders a DEM lit by the sun and the sky with ambient aperture lighting (headless).\n"
      "Without --aperture, the aperture map is baked once and cached (see aal-bake).",
      "aal-render");
  aal::RenderOptions o;
  aal::addRenderOptions(app, o);
  return aal::runTool(app, argc, argv, [&] { return run(o); });
}
