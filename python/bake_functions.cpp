// _bake and _relief: aal-bake's and aal-relief's work on an array
// (tools/aal_bake.cpp, tools/aal_relief.cpp), with the same library calls in
// the same order, so that the results equal the tools' bit for bit.
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <tbb/global_control.h>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/sky_view_factor_tiles.h"
#include "aperture/python/bindings.h"
#include "aperture/python/interruptible.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/reference/relief.h"
#include "aperture/terrain/units.h"
#include "aperture/tools/tool_options.h"

namespace py = pybind11;

namespace aal::python {

namespace {

// `threads` > 0 caps oneTBB's workers while it lives, as aal-bake --threads.
std::optional<tbb::global_control> threadLimit(int threads) {
  if (threads <= 0) return std::nullopt;
  return std::optional<tbb::global_control>(
      std::in_place, tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
}

void checkThreads(int threads) {
  if (threads < 0 || threads > 1024) {
    throw InputError("threads must be in [1, 1024] (or None: every core), got " +
                     std::to_string(threads));
  }
}

struct BakeOutput {
  int width = 0, height = 0;
  std::vector<float> visible, skyViewFactor, bentNormal, arcLength, horizonsDeg;
  std::vector<float> positiveOpenness, negativeOpenness;  // empty unless asked
  int horizonDirections = 0;
};

BakeOutput bakeArray(Task& task, DemArray dem, BakeOptions options, int threads) {
  const Heightfield field = toHeightfield(std::move(dem));
  task.throwIfCancelled();
  options.progress = [&task](double fraction) { task.report(fraction); };
  options.cancel = &task.cancel();
  const std::optional<tbb::global_control> limit = threadLimit(threads);
  BakeResult result = bakeApertures(field, options);

  BakeOutput out;
  out.width = field.width;
  out.height = field.height;
  const size_t texels = field.texelCount();
  const TexelWindow whole{.width = field.width, .height = field.height};
  // As aal-bake's --visible and --svf: voids are NaN (markVoidsAsNodata).
  out.skyViewFactor = std::move(result.skyViewFactor);
  markVoidsAsNodata(out.skyViewFactor, field, whole);
  out.positiveOpenness = std::move(result.positiveOpenness);
  out.negativeOpenness = std::move(result.negativeOpenness);
  if (options.positiveOpenness) markVoidsAsNodata(out.positiveOpenness, field, whole);
  if (options.negativeOpenness) markVoidsAsNodata(out.negativeOpenness, field, whole);
  if (options.apertureMap) {
    out.visible = std::move(result.visibleFraction);
    markVoidsAsNodata(out.visible, field, whole);
    out.arcLength.resize(texels);
    out.bentNormal.resize(3 * texels);
    const std::vector<float>& t = result.aperture.texels;
    for (size_t i = 0; i < texels; ++i) {
      for (int c = 0; c < 3; ++c) out.bentNormal[3 * i + c] = t[4 * i + c];
      out.arcLength[i] = t[4 * i + 3];
    }
    markVoidsAsNodata(out.arcLength, field, whole);
  }
  if (options.horizons) {
    const HorizonMap& h = result.horizons;
    out.horizonDirections = h.directions;
    out.horizonsDeg.resize(h.codes.size());
    for (size_t i = 0; i < h.codes.size(); ++i) {
      out.horizonsDeg[i] = static_cast<float>(degrees(decodeHorizon(h.codes[i], h.bits)));
    }
  }
  if (field.voidCount > 0) {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const size_t n = static_cast<size_t>(out.horizonDirections);
    for (size_t i = 0; i < texels; ++i) {
      if (field.voidMask[i] == 0) continue;
      if (!out.bentNormal.empty()) std::fill_n(&out.bentNormal[3 * i], 3, nan);
      if (n > 0) std::fill_n(&out.horizonsDeg[n * i], n, nan);
    }
  }
  return out;
}

py::tuple bake(DemArray& demObject, int azimuths, double maxDistanceM, const std::string& edge,
               bool curvature, double refraction, int horizons, bool openness, bool apertures,
               int threads, const py::object& progress) {
  if (edge != "open" && edge != "clamp") {
    throw InputError("edge must be 'open' or 'clamp', got '" + edge + "'");
  }
  checkThreads(threads);
  // aal-bake's options (applySweepOptions, tools/bake_command_line.h), the
  // sky-view factor always: it costs a sum per texel.
  BakeOptions options;
  options.method = BakeMethod::Sweep;
  options.azimuths = azimuths;
  options.clampEdge = edge == "clamp";
  options.curvature = curvature;
  options.refraction = refraction;
  options.maxDistanceM = maxDistanceM;
  options.skyViewFactor = true;
  // Without the apertures (sky_view_factor, openness) no map is summed, as
  // aal-bake without -o: the same rasters, about a fifth faster.
  options.apertureMap = options.visibleFraction = apertures;
  // Both, as aal-bake --openness-positive and --openness-negative.
  options.positiveOpenness = options.negativeOpenness = openness;
  if (openness && curvature) {
    throw InputError(
        "openness does not take curvature (the negative openness's sweep of the "
        "inverted DEM would raise distant terrain, not drop it)");
  }
  options.horizons = horizons != 0;
  if (options.horizons) options.horizonDirections = horizons;
  options.horizonBits = kHorizonBits;
  DemArray dem = takeDem(demObject);
  BakeOutput out = runInterruptible(
      progress, [&](Task& task) { return bakeArray(task, std::move(dem), options, threads); });
  const py::ssize_t h = out.height, w = out.width;
  py::object horizonArray = py::none();
  if (out.horizonDirections > 0) {
    horizonArray = toNumpy(std::move(out.horizonsDeg), {h, w, out.horizonDirections});
  }
  py::object positive = py::none(), negative = py::none();
  if (openness) {
    positive = toNumpy(std::move(out.positiveOpenness), {h, w});
    negative = toNumpy(std::move(out.negativeOpenness), {h, w});
  }
  py::object visible = py::none(), bentNormal = py::none(), arcLength = py::none();
  if (apertures) {
    visible = toNumpy(std::move(out.visible), {h, w});
    bentNormal = toNumpy(std::move(out.bentNormal), {h, w, 3});
    arcLength = toNumpy(std::move(out.arcLength), {h, w});
  }
  return py::make_tuple(visible, toNumpy(std::move(out.skyViewFactor), {h, w}), bentNormal,
                        arcLength, horizonArray, positive, negative);
}

// aal-relief's sky weight when --sky is not given (tools/aal_relief.cpp).
constexpr double kDefaultSkyWeight = 0.2;

struct ReliefArguments {
  std::string lighting;  // sun, sky, multidirectional
  double sunAzimuthDeg = kDefaultSunAzimuthDeg, sunElevationDeg = kDefaultSunElevationDeg;
  std::optional<std::string> time;
  std::optional<double> lat, lon;
  double sunRadiusDeg = kSunAngularRadiusDeg;
  std::optional<double> skyWeight;
  std::string mode;
  bool obscurance = true;
  std::optional<double> obscuranceRadiusM;
  int obscuranceSamples = 16, obscuranceSteps = 1;
  std::optional<double> waterLevelM;
  bool floatFormat = false;
  double stretchLow = 0, stretchHigh = 1;
  int threads = 0;
};

struct ReliefOutput {
  int width = 0, height = 0;
  std::vector<float> value;
  std::vector<uint8_t> grey;
};

ReliefOutput reliefOfArray(Task& task, DemArray dem, const ReliefArguments& a) {
  const Heightfield field = toHeightfield(std::move(dem));
  requireRenderableDem(field);
  ReliefSettings s;
  s.outWidth = field.width;
  s.outHeight = field.height;
  s.mode = a.mode == "exact" ? ShadingMode::Exact : ShadingMode::Approx;
  s.sunRadiusDeg = a.sunRadiusDeg;
  s.skyWeight = static_cast<float>(a.skyWeight.value_or(kDefaultSkyWeight));
  s.lighting = a.lighting == "sky"                ? ReliefLighting::SkyOnly
               : a.lighting == "multidirectional" ? ReliefLighting::Multidirectional
                                                  : ReliefLighting::Sun;
  s.sunAzimuthDeg = a.sunAzimuthDeg;
  s.sunElevationDeg = a.sunElevationDeg;
  if (a.time) {
    const SolarPosition sun = sunAtTime(*a.time, a.lat, a.lon, field);
    s.sunAzimuthDeg = sun.azimuthDeg;
    s.sunElevationDeg = sun.elevationDeg;
  }
  s.obscurance = obscuranceFromOptions(a.obscurance, a.obscuranceSamples, a.obscuranceSteps,
                                       a.obscuranceRadiusM, field);
  s.waterLevelM = a.waterLevelM;

  const std::optional<tbb::global_control> limit = threadLimit(a.threads);
  // aal-relief's map: the bake of BakeOptions{} (its cache's), as halves.
  BakeOptions options;
  options.progress = [&task](double fraction) { task.report(0.5 * fraction); };
  options.cancel = &task.cancel();
  HalfApertureMap map = toHalfApertureMap(bakeApertures(field, options).aperture);
  task.throwIfCancelled();
  ReliefImage relief =
      shadeRelief(field, map, s, [&task](double fraction) { task.report(0.5 + 0.5 * fraction); });

  ReliefOutput out;
  out.width = relief.width;
  out.height = relief.height;
  if (a.floatFormat) {
    out.value = std::move(relief.value);  // NaN at voids, as aal-relief --format float
    return out;
  }
  // aal-relief's 8-bit output: gdaldem's scale, 1 + 254 v, 0 at voids.
  const double low = a.stretchLow, high = a.stretchHigh;
  out.grey.resize(relief.value.size());
  for (size_t i = 0; i < relief.value.size(); ++i) {
    const float stretched =
        static_cast<float>(std::clamp((relief.value[i] - low) / (high - low), 0.0, 1.0));
    out.grey[i] = relief.isVoid(i) ? 0 : static_cast<uint8_t>(1 + std::lround(254.0 * stretched));
  }
  return out;
}

py::array relief(DemArray& demObject, ReliefArguments a, const py::object& progress) {
  if (a.lighting != "sun" && a.lighting != "sky" && a.lighting != "multidirectional") {
    throw InputError("lighting must be 'sun', 'sky' or 'multidirectional', got '" + a.lighting +
                     "'");
  }
  if (a.mode != "approx" && a.mode != "exact") {
    throw InputError("mode must be 'approx' or 'exact', got '" + a.mode + "'");
  }
  if (a.time && !parseIso8601Utc(*a.time)) {
    throw InputError("time must be ISO 8601, e.g. 2024-06-21T12:00:00Z, got '" + *a.time + "'");
  }
  checkThreads(a.threads);
  DemArray dem = takeDem(demObject);
  ReliefOutput out = runInterruptible(
      progress, [&](Task& task) { return reliefOfArray(task, std::move(dem), a); });
  const py::ssize_t h = out.height, w = out.width;
  if (a.floatFormat) return toNumpy(std::move(out.value), {h, w});
  return toNumpy(std::move(out.grey), {h, w});
}

}  // namespace

void addBakeFunctions(py::module_& m) {
  m.def("_bake", &bake, py::arg("dem"), py::arg("azimuths"), py::arg("max_distance"),
        py::arg("edge"), py::arg("curvature"), py::arg("refraction"), py::arg("horizons"),
        py::arg("openness"), py::arg("apertures") = true, py::arg("threads"), py::arg("progress"),
        "aal-bake's in-memory bake of a _Dem: (visible, sky_view_factor, bent_normal, "
        "arc_length, horizons or None, positive and negative openness or None); without "
        "apertures, visible, bent_normal and arc_length are None. Use aperture.bake.");
  m.def(
      "_relief",
      [](DemArray& dem, const std::string& lighting, double sunAzimuth, double sunElevation,
         std::optional<std::string> time, std::optional<double> lat, std::optional<double> lon,
         double sunRadius, std::optional<double> sky, const std::string& mode, bool obscurance,
         std::optional<double> obscuranceRadius, int obscuranceSamples, int obscuranceSteps,
         std::optional<double> waterLevel, bool floatFormat, double stretchLow, double stretchHigh,
         int threads, const py::object& progress) {
        ReliefArguments a;
        a.lighting = lighting;
        a.sunAzimuthDeg = sunAzimuth;
        a.sunElevationDeg = sunElevation;
        a.time = std::move(time);
        a.lat = lat;
        a.lon = lon;
        a.sunRadiusDeg = sunRadius;
        a.skyWeight = sky;
        a.mode = mode;
        a.obscurance = obscurance;
        a.obscuranceRadiusM = obscuranceRadius;
        a.obscuranceSamples = obscuranceSamples;
        a.obscuranceSteps = obscuranceSteps;
        a.waterLevelM = waterLevel;
        a.floatFormat = floatFormat;
        a.stretchLow = stretchLow;
        a.stretchHigh = stretchHigh;
        a.threads = threads;
        return relief(dem, std::move(a), progress);
      },
      py::arg("dem"), py::arg("lighting"), py::arg("sun_azimuth"), py::arg("sun_elevation"),
      py::arg("time"), py::arg("lat"), py::arg("lon"), py::arg("sun_radius"), py::arg("sky"),
      py::arg("mode"), py::arg("obscurance"), py::arg("obscurance_radius"),
      py::arg("obscurance_samples"), py::arg("obscurance_steps"), py::arg("water_level"),
      py::arg("float_format"), py::arg("stretch_low"), py::arg("stretch_high"), py::arg("threads"),
      py::arg("progress"),
      "aal-relief's shaded relief of a _Dem: uint8 (H, W), or float32 with float_format. Use "
      "aperture.relief.");
}

}  // namespace aal::python
