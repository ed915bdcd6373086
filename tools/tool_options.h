// Option values shared by the tools' command lines (aal-render, aal-view):
// image sizes and points in the DEM frame. Errors are InputError (exit 2).
#pragma once

#include <cmath>
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/light/lighting_defaults.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/view/camera.h"
#include "aperture/terrain/view/camera_path.h"

namespace aal {

// checkOutputWritable for a path the user gave: an output that cannot be
// written is bad input (exit 2), found before any work starts.
inline void requireWritableOutput(const std::string& path) {
  try {
    checkOutputWritable(path);
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
}

// "X,Y,Z" in metres; `name` (the option) goes into the message.
inline glm::dvec3 parseTriple(const std::string& name, const std::string& text) {
  glm::dvec3 v;
  char c1 = 0, c2 = 0;
  std::istringstream in(text);
  if (!(in >> v.x >> c1 >> v.y >> c2 >> v.z) || c1 != ',' || c2 != ',' || !in.eof() ||
      !std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
    throw InputError(name + " must be X,Y,Z in metres, got '" + text + "'");
  }
  return v;
}

// "WIDTHxHEIGHT" with positive sides up to 65536; `name` (the option) goes
// into the message.
inline std::pair<uint32_t, uint32_t> parseSize(const std::string& text,
                                               const std::string& name = "--size") {
  long w = 0, h = 0;
  char x = 0;
  std::istringstream in(text);
  if (!(in >> w >> x >> h) || (x != 'x' && x != 'X') || !in.eof() || w <= 0 || h <= 0 ||
      w > 65536 || h > 65536) {
    throw InputError(name + " must be WIDTHxHEIGHT with positive sides, got '" + text + "'");
  }
  return {static_cast<uint32_t>(w), static_cast<uint32_t>(h)};
}

// The sun at `time` (ISO 8601, UTC) seen from `lat`, `lon`, each defaulting
// to the DEM's place (lighting_defaults.h): --time, --lat, --lon.
inline SolarPosition sunAtTime(const std::string& time, std::optional<double> lat,
                               std::optional<double> lon, const Heightfield& field) {
  const std::optional<UtcTime> utc = parseIso8601Utc(time);
  if (!utc) {
    throw InputError("--time must be ISO 8601, e.g. 2024-06-21T12:00:00Z, got '" + time + "'");
  }
  const GeoPlace place = defaultSunPlace(field);
  return solarPosition(*utc, lat.value_or(place.latitudeDeg), lon.value_or(place.longitudeDeg));
}

// Obscurance settings from --no-obscurance, --obscurance-samples, -steps
// and -radius (default: obscurance.h's for the DEM), checked against it.
inline ObscuranceSettings obscuranceFromOptions(bool enabled, int samples, int steps,
                                                std::optional<double> radiusM,
                                                const Heightfield& field) {
  ObscuranceSettings s;
  s.enabled = enabled;
  s.samples = samples;
  s.steps = steps;
  const glm::dvec2 extent = demExtentM(field);
  s.radiusM = radiusM ? static_cast<float>(*radiusM)
                      : defaultObscuranceRadiusM({field.cellSizeXM, field.cellSizeYM}, extent);
  checkObscuranceSettings(s, extent);
  return s;
}

// Throws InputError unless `field` has a surface to light: the renderers
// draw cells between texels and derive ranges (obscurance radius, camera
// distance) from its extent, which a single row or column does not have.
inline void requireRenderableDem(const Heightfield& field) {
  if (field.width >= 2 && field.height >= 2) return;
  throw InputError(field.source + ": " + std::to_string(field.width) + " x " +
                   std::to_string(field.height) +
                   " texels have no surface to render; rendering needs at least 2 x 2 "
                   "(aal-bake and aal-info take any size)");
}

// Throws InputError when `point` (what: "--camera 1,2,3", "camera path P
// line 4: the camera") lies beyond cameraReachM of the DEM's centre.
inline void requireWithinCameraReach(const std::string& what, const glm::dvec3& point,
                                     const Heightfield& field) {
  // hypot: the length of (1e300, 0, 0) overflows as a sum of squares.
  const double distance = std::hypot(point.x, std::hypot(point.y, point.z));
  const double reach = cameraReachM(field);
  if (distance <= reach) return;
  std::ostringstream message;
  message << what << " lies " << distance << " m from the DEM's centre, beyond the " << reach
          << " m a camera and the point it looks at may be from it (10,000 km, or "
          << kCameraReachDiagonals
          << " DEM diagonals when more): give a point closer to the DEM (metres in the DEM "
             "frame, origin at its centre)";
  throw InputError(message.str());
}

// requireWithinCameraReach for every keyframe of a camera path (`file`).
inline void requireCameraPathWithinReach(const CameraPath& path, const std::string& file,
                                         const Heightfield& field) {
  for (const CameraKeyframe& key : path.keyframes()) {
    const std::string where = "camera path " + file + " line " + std::to_string(key.line) + ": ";
    requireWithinCameraReach(where + "the camera", key.camera.position, field);
    requireWithinCameraReach(where + "the look-at point", key.camera.lookAt, field);
  }
}

// Throws InputError when the camera has no direction: --camera at --look-at.
inline void requireCameraDirection(const glm::dvec3& position, const glm::dvec3& lookAt) {
  if (glm::length(lookAt - position) >= 1e-6) return;
  throw InputError("--camera and --look-at are the same point; the camera needs a direction");
}

}  // namespace aal
