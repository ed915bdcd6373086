// Angles and the sun's size and default place in the sky: one definition for
// every layer (terrain, engine, preprocess, tools, the Python bindings), so
// that no two files convert degrees with constants of their own.
#pragma once

#include <numbers>

namespace aal {

inline constexpr double kPi = std::numbers::pi;
// In single precision, for the float math that mirrors the shaders.
inline constexpr float kPiFloat = static_cast<float>(kPi);
static_assert(kPiFloat == std::numbers::pi_v<float>);

inline constexpr double kRadiansPerDegree = kPi / 180.0;
inline constexpr double kDegreesPerRadian = 180.0 / kPi;

constexpr double radians(double deg) {
  return deg * kRadiansPerDegree;
}

constexpr double degrees(double rad) {
  return rad * kDegreesPerRadian;
}

// Angular radius of the sun's disk at 1 AU, degrees (docs/design.md §7).
inline constexpr double kSunAngularRadiusDeg = 0.26656;

// kSunAngularRadiusDeg in radians (0.0046524) as the renderers' default
// (Lighting, ShadingInputs), rounded as the renders and golden images have
// always had it. The tools pass the exact value of their --sun-radius.
inline constexpr float kSunRadiusRad = 0.004653f;
static_assert(kSunRadiusRad - radians(kSunAngularRadiusDeg) < 1e-6 &&
                  radians(kSunAngularRadiusDeg) - kSunRadiusRad < 1e-6,
              "kSunRadiusRad must stay kSunAngularRadiusDeg, rounded");

// The sun when none is given: from the north-west, 45 degrees up, as
// gdaldem hillshade lights by default (degrees clockwise from north).
inline constexpr double kDefaultSunAzimuthDeg = 315.0;
inline constexpr double kDefaultSunElevationDeg = 45.0;

}  // namespace aal
