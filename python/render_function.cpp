// _render: aal-render's headless frame of an array (tools/aal_render.cpp, its
// single-image path with the aperture map baked in memory), read back as
// RGBA8 instead of written as a PNG.
#include <pybind11/stl.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

#include "aperture/engine/supersampling.h"
#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/engine/vk/instance.h"
#include "aperture/preprocess/bake.h"
#include "aperture/python/bindings.h"
#include "aperture/python/interruptible.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/sky_lighting.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/units.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/tools/horizon_option.h"
#include "aperture/tools/tool_options.h"

namespace py = pybind11;

namespace aal::python {

namespace {

struct RenderArguments {
  uint32_t width = 1280, height = 720;
  std::optional<std::array<double, 3>> camera, lookAt;
  double fovDeg = 40;
  double sunAzimuthDeg = kDefaultSunAzimuthDeg, sunElevationDeg = kDefaultSunElevationDeg;
  std::optional<std::string> time;
  std::optional<double> lat, lon;
  double sunRadiusDeg = kSunAngularRadiusDeg;
  double turbidity = kDefaultTurbidity;
  std::optional<double> ev100, visibilityKm;
  std::string mode = "approx";
  bool transparentBackground = false;
  std::optional<std::array<double, 3>> albedo;
  bool obscurance = true;
  std::optional<double> obscuranceRadiusM;
  int obscuranceSamples = ObscuranceSettings{}.samples, obscuranceSteps = 1;
  std::optional<double> waterLevelM;
  int anisotropy = kDefaultFootprintProbes;
  uint32_t supersample = 1;  // points per pixel per axis (engine/supersampling.h)
  double exaggeration = 1.0;
  int device = -1;
  int threads = 0;
};

glm::dvec3 toVec(const std::array<double, 3>& v) {
  return {v[0], v[1], v[2]};
}

struct Frame {
  uint32_t width = 0, height = 0;
  std::vector<uint8_t> rgba;
};

Frame renderArray(Task& task, DemArray dem, const RenderArguments& a) {
  const ShadingMode mode = toolShadingModes().at(a.mode);
  const Heightfield field = toHeightfield(std::move(dem));
  requireRenderableDem(field);
  const ObscuranceSettings obscurance = obscuranceFromOptions(
      a.obscurance, a.obscuranceSamples, a.obscuranceSteps, a.obscuranceRadiusM, field);

  std::optional<tbb::global_control> limit;
  if (a.threads > 0) {
    limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(a.threads));
  }
  // aal-render's map is its cache's, the bake of BakeOptions{}; the horizon
  // mode's horizons those of aal-bake --horizons (16 directions, 8 bits),
  // which the same sweep keeps.
  BakeOptions options;
  options.horizons = mode == ShadingMode::Horizon;
  options.horizonDirections = kBakeToolHorizonDirections;
  options.horizonBits = kBakeToolHorizonBits;
  options.progress = [&task](double fraction) { task.report(0.9 * fraction); };
  options.cancel = &task.cancel();
  BakeResult baked = bakeApertures(field, options);
  task.throwIfCancelled();

  SolarPosition sun;
  if (a.time) {
    sun = sunAtTime(*a.time, a.lat, a.lon, field);
  } else {
    sun.azimuthDeg = a.sunAzimuthDeg;
    sun.elevationDeg = a.sunElevationDeg;
  }
  FrameSettings settings;
  settings.mode = mode;
  settings.obscurance = obscurance;
  settings.anisotropy = a.anisotropy;
  if (a.albedo) settings.albedoValue = glm::vec3(toVec(*a.albedo));
  const double aspect = double(a.width) / double(a.height);
  settings.camera = defaultCamera(field, aspect, a.fovDeg, 0.0);
  if (a.camera) settings.camera.position = toVec(*a.camera);
  if (a.lookAt) settings.camera.lookAt = toVec(*a.lookAt);
  requireCameraDirection(settings.camera.position, settings.camera.lookAt);
  settings.camera.verticalFovDeg = a.fovDeg;
  settings.transparentBackground = a.transparentBackground;
  Lighting& light = settings.lighting;
  light = defaultLighting(field, sun.azimuthDeg, sun.elevationDeg, a.turbidity, sun.sunDistanceAu);
  light.sunRadiusRad = static_cast<float>(radians(a.sunRadiusDeg));
  if (a.visibilityKm) {
    light.hazeDensityPerM = static_cast<float>(hazeDensityForVisibility(*a.visibilityKm * 1000));
  }
  if (a.ev100) light.exposure = exposureFromEv100(static_cast<float>(*a.ev100));
  if (a.waterLevelM) settings.waterLevelM = static_cast<float>(*a.waterLevelM * a.exaggeration);

  Frame out;
  out.width = a.width;
  out.height = a.height;
  Instance instance;  // the validation layer when AAL_VALIDATION=1
  {
    Device device(instance, a.device);
    const uint32_t largest = device.properties().limits.maxImageDimension2D;
    if (a.width > largest || a.height > largest) {
      throw InputError("size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                       " exceeds the device's largest image (" + std::to_string(largest) + ")");
    }
    if (uint64_t{a.width} * a.supersample > largest ||
        uint64_t{a.height} * a.supersample > largest) {
      throw InputError("size " + std::to_string(a.width) + "x" + std::to_string(a.height) +
                       " with supersample " + std::to_string(a.supersample) +
                       " exceeds the device's largest image (" + std::to_string(largest) + ")");
    }
    TerrainScene scene(device, field, baked.aperture, nullptr, kDefaultTriangleBudget,
                       TerrainTiling{});
    baked.aperture = {};
    if (options.horizons) {
      auto horizons = std::make_shared<const HorizonMap>(std::move(baked.horizons));
      const float azimuth = sunAzimuthRad(settings.lighting.sunDirection);
      scene.setHorizons(device, horizons, horizonPairFor(horizons->directions, azimuth, -1));
    }
    task.throwIfCancelled();
    TerrainRenderer renderer(device, a.width * a.supersample, a.height * a.supersample);
    FrameResult frame = renderSupersampled(renderer, scene, settings, a.supersample, false);
    out.rgba = std::move(frame.display);
  }  // the device's destruction is validated too
  if (instance.validationEnabled() && instance.validationLog().count() > 0) {
    const std::vector<std::string> messages = instance.validationLog().messages();
    std::string text = "the Vulkan validation layer (AAL_VALIDATION=1) reported " +
                       std::to_string(messages.size()) + " message(s):";
    for (const std::string& message : messages) text += "\n" + message;
    throw std::runtime_error(text);
  }
  task.report(1.0);
  return out;
}

py::array render(DemArray& demObject, RenderArguments a, const py::object& progress) {
  if (toolShadingModes().count(a.mode) == 0) {
    std::string names;
    for (const auto& [name, unused] : toolShadingModes()) {
      names += (names.empty() ? "" : ", ") + name;
    }
    throw InputError("mode must be one of " + names + "; got '" + a.mode + "'");
  }
  if (a.time && !parseIso8601Utc(*a.time)) {
    throw InputError("time must be ISO 8601, e.g. 2024-06-21T12:00:00Z, got '" + *a.time + "'");
  }
  if (a.width < 1 || a.height < 1 || a.width > 65536 || a.height > 65536) {
    throw InputError("size must be (width, height) with sides in [1, 65536], got (" +
                     std::to_string(a.width) + ", " + std::to_string(a.height) + ")");
  }
  a.exaggeration = demObject.exaggeration;
  DemArray dem = takeDem(demObject);
  Frame frame =
      runInterruptible(progress, [&](Task& task) { return renderArray(task, std::move(dem), a); });
  return toNumpy(std::move(frame.rgba), {py::ssize_t(frame.height), py::ssize_t(frame.width), 4});
}

}  // namespace

void addRenderFunction(py::module_& m) {
  m.def(
      "_render",
      [](DemArray& dem, uint32_t width, uint32_t height,
         std::optional<std::array<double, 3>> camera, std::optional<std::array<double, 3>> lookAt,
         double fov, double sunAzimuth, double sunElevation, std::optional<std::string> time,
         std::optional<double> lat, std::optional<double> lon, double sunRadius, double turbidity,
         std::optional<double> ev, std::optional<double> visibilityKm, const std::string& mode,
         bool transparent, std::optional<std::array<double, 3>> albedo, bool obscurance,
         std::optional<double> obscuranceRadius, int obscuranceSamples, int obscuranceSteps,
         std::optional<double> waterLevel, int anisotropy, uint32_t supersample, int device,
         int threads, const py::object& progress) {
        RenderArguments a;
        a.width = width;
        a.height = height;
        a.camera = camera;
        a.lookAt = lookAt;
        a.fovDeg = fov;
        a.sunAzimuthDeg = sunAzimuth;
        a.sunElevationDeg = sunElevation;
        a.time = std::move(time);
        a.lat = lat;
        a.lon = lon;
        a.sunRadiusDeg = sunRadius;
        a.turbidity = turbidity;
        a.ev100 = ev;
        a.visibilityKm = visibilityKm;
        a.mode = mode;
        a.transparentBackground = transparent;
        a.albedo = albedo;
        a.obscurance = obscurance;
        a.obscuranceRadiusM = obscuranceRadius;
        a.obscuranceSamples = obscuranceSamples;
        a.obscuranceSteps = obscuranceSteps;
        a.waterLevelM = waterLevel;
        a.anisotropy = anisotropy;
        a.supersample = supersample;
        a.device = device;
        a.threads = threads;
        return render(dem, std::move(a), progress);
      },
      py::arg("dem"), py::arg("width"), py::arg("height"), py::arg("camera"), py::arg("look_at"),
      py::arg("fov"), py::arg("sun_azimuth"), py::arg("sun_elevation"), py::arg("time"),
      py::arg("lat"), py::arg("lon"), py::arg("sun_radius"), py::arg("turbidity"), py::arg("ev"),
      py::arg("visibility"), py::arg("mode"), py::arg("transparent"), py::arg("albedo"),
      py::arg("obscurance"), py::arg("obscurance_radius"), py::arg("obscurance_samples"),
      py::arg("obscurance_steps"), py::arg("water_level"), py::arg("anisotropy"),
      py::arg("supersample"), py::arg("device"), py::arg("threads"), py::arg("progress"),
      "aal-render's frame of a _Dem as RGBA8 (H, W, 4). Use aperture.render.");
}

}  // namespace aal::python
