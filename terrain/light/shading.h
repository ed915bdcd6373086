// Ambient aperture lighting of one surface point: docs/design.md §5. The GLSL
// twin is shaders/shading.glsl (checked for parity on the device by the tests).
//
// Radiometry: albedo a in [0, 1]; irradiances E (sun at normal incidence)
// and radiances L (sky) in one linear RGB unit (terrain/light/atmosphere.h); the
// result is outgoing radiance a/pi * E in that unit.
#pragma once

#include <map>
#include <string>

#include <glm/vec3.hpp>

#include "aperture/shaders/config.h"
#include "aperture/terrain/light/lighting.h"

namespace aal {

enum class ShadingMode : int {
  Approx = AAL_MODE_APPROX,                        // Oat's smoothstep cap intersection
  Exact = AAL_MODE_EXACT,                          // exact cap intersection
  BaselineLambert = AAL_MODE_BASELINE_LAMBERT,     // N.L, no shadow, constant sky ambient
  BaselineAo = AAL_MODE_BASELINE_AO,               // N.L, sky ambient scaled by Omega/2pi
  DebugVisible = AAL_MODE_DEBUG_VISIBLE,           // Omega/2pi as grey
  DebugBentNormal = AAL_MODE_DEBUG_BENT_NORMAL,    // B * 0.5 + 0.5
  DebugSunFraction = AAL_MODE_DEBUG_SUN_FRACTION,  // visible fraction f of the sun disk
  DebugSkyFill = AAL_MODE_DEBUG_SKY_FILL,          // E_sky / (pi L_sky) as grey
  // The obscurance pass's O as grey and W as RGB (docs/design.md §6): shade()
  // returns the transfer input, which the renderer sets to O or W.
  DebugObscurance = AAL_MODE_DEBUG_OBSCURANCE,
  DebugTransfer = AAL_MODE_DEBUG_TRANSFER,
  // The sun's visible fraction from the directional horizon at its azimuth
  // (ShadingInputs::sunHorizonRad, terrain/io/horizon_map.h), the sky fill from
  // the aperture as in Approx, less the part of the sun the horizon leaves in
  // view (Approx: the sun's cap within the aperture's); no cap intersection.
  Horizon = AAL_MODE_HORIZON,
};

// Command-line / UI names of the modes (aal-render --mode, the viewer's panel).
const std::map<std::string, ShadingMode>& shadingModeNames();

struct ShadingInputs {
  glm::vec3 albedo{0.2f};
  glm::vec3 normal{0, 0, 1};           // unit shading normal N
  glm::vec3 bentNormal{0, 0, 1};       // unit bent normal B (aperture centre)
  float apertureRad = 1.5707963f;      // aperture cap arc length r_a
  glm::vec3 sunDirection{0, 0, 1};     // unit L
  float sunRadiusRad = kSunRadiusRad;  // r_s
  glm::vec3 sunIrradiance{0.0f};       // E_sun at normal incidence
  glm::vec3 skyRadiance{0.0f};         // average sky radiance L_sky
  glm::vec3 transfer{1.0f};  // ambient transfer W (docs/design.md §6), 1 if nothing is near
  // Horizon mode: the horizon's elevation in the sun's azimuth (rad), its
  // mean over the footprint, and its variance there (rad^2;
  // terrain/light/horizon_moments.h).
  float sunHorizonRad = -1.5707963f;
  float sunHorizonVarianceRad2 = 0.0f;
  // approx, exact: the spread (standard deviation, rad) over the pixel's
  // footprint of the sun's distance from the aperture's edge
  // (sunEdgeFootprintDistance); 0: a point, the cap intersection as it is.
  float sunEdgeSpreadRad = 0;
};

struct ShadingTerms {
  glm::vec3 direct{0.0f};
  glm::vec3 ambient{0.0f};
  float sunFraction = 0;          // f: the part of the sun's disk seen through the aperture
  glm::vec3 skyIrradiance{0.0f};  // E_sky
};

struct CapIntersectionTable;

// The footprint's mean of the sun's visible part at the aperture's edge
// (docs/rendering.md, "The sun's edge over the footprint"). Over a pixel's
// footprint the distance d between the sun's and the aperture's centres
// varies by `spreadRad` (a standard deviation) around its mean, and the
// pixel sees the mean of the cap intersection's step across it: a step as
// wide as the sun convolved with the spread. Modelled as the same step
// widened to the sun radius whose transition has the step's variance plus
// the spread's (smoothstep over +-r: variance r^2 / 5, so sqrt(r_s^2 + 5
// spread^2)), at most AAL_SUN_EDGE_MAX_WIDENING_RAD wider, and evaluated
// with the true sun at the distance that maps the widened transition onto
// its own: r_a + (d - r_a) r_s / widened. Returns d unchanged for no
// spread, or an aperture no larger than the sun.
float sunEdgeFootprintDistance(float apertureRad, float sunRadiusRad, float dRad, float spreadRad);

// The part of the sun's disk (angular radius sunRadiusRad, centre at
// elevation sunElevationRad) above a horizon at elevation horizonRad: the
// disk cut by a straight line (the horizon is straight at the sun's scale),
// 1 - (acos x - x sqrt(1 - x^2)) / pi with x = (e - h) / r_s in [-1, 1].
float horizonSunFraction(float sunElevationRad, float horizonRad, float sunRadiusRad);

// The share of the sun's disk above the horizon, expected over a footprint
// whose horizons have this mean and variance (horizon_moments.h): the disk's
// fraction above a straight horizon, as a function of the horizon, falls
// like the distribution of a semicircle of radius r_s (variance r_s^2 / 4);
// averaged over horizons spread with the variance v it falls like their sum,
// which a semicircle of radius sqrt(r_s^2 + 4 v) matches in mean and
// variance. So: horizonSunFraction with that radius, exact where v = 0.
// Chosen by measurement over Gaussian and Chebyshev estimators
// (docs/rendering.md, "Prefiltering the horizons: moments").
float horizonMomentSunFraction(float sunElevationRad, float horizonMeanRad,
                               float horizonVarianceRad2, float sunRadiusRad);

// The terms of docs/design.md §5 for the AAL modes (approx/exact) and the baselines.
// Exact mode evaluates the closed form (capIntersectionExact, terrain/light/caps.h)
// or, given `exactTable` (made for in.sunRadiusRad), reads it from the table
// as the renderer's shaders do (terrain/light/cap_table.h).
ShadingTerms shadingTerms(const ShadingInputs& in, ShadingMode mode,
                          const CapIntersectionTable* exactTable = nullptr);

// Final linear value: direct + ambient, or the debug quantity of the mode.
glm::vec3 shade(const ShadingInputs& in, ShadingMode mode,
                const CapIntersectionTable* exactTable = nullptr);

}  // namespace aal
