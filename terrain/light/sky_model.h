// Analytic clear sky: Preetham, Shirley & Smits 1999, "A Practical Analytic
// Model for Daylight" (SIGGRAPH 99), with the night rule below.
//
// Model (paper §3 and App. A.2). For a view direction at zenith angle theta
// and angle gamma from the sun (sun zenith angle theta_s, turbidity T), each of
// Y (luminance) and the CIE chromaticities x, y follows Perez et al. 1993:
//   F(theta, gamma) = (1 + A e^(B / cos theta)) (1 + C e^(D gamma) + E cos^2 gamma)
//   Y = Y_z F_Y(theta, gamma) / F_Y(0, theta_s)       (paper eq. 3; same for x and y)
// with A..E linear in T (paper App. A.2, "distribution coefficients"), the
// zenith luminance (App. A.2, in kcd/m²)
//   Y_z = (4.0453 T - 4.9710) tan chi - 0.2155 T + 2.4192,  chi = (4/9 - T/120)(pi - 2 theta_s)
// and the zenith chromaticities x_z, y_z as the cubic-in-theta_s, quadratic-in-T
// polynomials of App. A.2. xyY goes to XYZ and then to linear Rec. 709 / sRGB
// (IEC 61966-2-1 matrix, D65), negative channels clamped to 0.
//
// Units: photometric RGB of atmosphere.h, radiance in kcd/m² (Y_z is in kcd/m²
// in the paper, so no extra scale is needed). With the sun 60° up at T = 2.5
// the zenith is 8.2 kcd/m² and the diffuse illuminance on a horizontal
// surface 27 klx, against ~98 klx of direct sun at normal incidence.
//
// Validity and the rules outside it:
// - Turbidity is clamped to [2, 10]. Below T ~ 1.65 the fitted factor
//   1 + A_Y e^(B_Y) (the zenith value of F_Y's first term, the normaliser)
//   crosses zero and the luminance blows up; at T = 1.7 the average sky is
//   already 2.6x that of T = 2. Above 10, Y_z turns negative for a low sun.
// - Views below the horizon use cos theta = max(cos theta, AAL_SKY_MIN_COS_THETA),
//   i.e. they see the horizon's value for their gamma; the renderer draws
//   terrain there anyway.
// - Night (twilight rule): the model is undefined for a sun below the horizon.
//   There the sky is the model with the sun moved up to the horizon (same
//   azimuth, theta_s = 90°), its luminance Y scaled by twilightFade(elevation):
//   1 above the horizon, 10^(0.4 e) smoothstep(-6°, 0°, e) below it (e in
//   degrees), i.e. the sky darkens ~0.4 decades per degree (the ratio of
//   horizontal illuminance at sunset, ~700 lx, to the end of civil twilight,
//   ~3 lx, over 6°) and is exactly black from -6° (end of civil twilight) on.
//   Chromaticity is kept: the twilight sky keeps the sunset colours.
//
// Chromaticity correction (daylight locus lift): near the horizon of a high
// sun the Perez fit of y dips below the CIE daylight locus (sun 77° up, T =
// 2.5, 3° above the horizon towards the sun: x = 0.310, y = 0.317 against the
// locus's 0.326), a green deficit that reads grey-lavender (linear sRGB R >
// G < B). Measured clear skies do not do that: their chromaticities lie close
// to the daylight locus along every meridian (Hernández-Andrés, Romero & Lee
// 2001, "Colorimetric and spectroradiometric characteristics of narrow-field-
// of-view clear skylight in Granada, Spain", JOSA A 18(2)), which is the curve
// the CIE fitted to measured daylight (Judd, MacAdam & Wyszecki 1964; CIE
// 15:2004 eq. 3.3, y_D = -3.000 x² + 2.870 x - 0.275). So y is raised to
// y_D(x) where it lies below it, x and the luminance Y are kept: the sky's
// brightness, and so every irradiance derived from it, is unchanged; a
// pale-blue horizon (B > G > R) results wherever x is bluer than D65's. Skies
// on or above the locus (the blue sky away from the horizon, sunsets, x >
// 0.35) are untouched. docs/sun-and-sky.md has the numbers.
//
// Midday colour-temperature floor: under a sun 45° or more up the Perez x fit
// still warms the last few degrees above the horizon towards the sun (sun 60°
// up, 3° above the horizon: x = 0.318, CCT ~6200 K, R > G > B). A spectral
// single-scattering reference (tests/terrain/light/single_scattering_sky.h, after
// Nishita et al. 1993) puts that band between ~5800 K (Preetham's aerosol at
// T = 2.5) and ~8300 K (no aerosol): near white either way, its sign of
// B - R set by the haze. The renderer takes the clear end: by day the sky's
// chromaticity is slid along the daylight locus to no warmer than 6800 K
// (x <= x_D(6800 K), the offset from the locus kept), which the reference
// gives for a very clear atmosphere, and which reads B > G > R after the
// tone map. The floor fades in with the sun from 30° to 45° up (smoothstep),
// so the morning, evening and winter-noon horizons keep their warmth and
// sunsets are untouched. Luminance is kept.
//
// Known limitation: sunsets and high turbidity are the model's weak points
// (Hosek & Wilkie 2012; Zotti, Wilkie & Purgathofer 2007, "A Critical Review
// of the Preetham Skylight Model"): its sky is too bright for a low sun
// (10.7 klx of diffuse illuminance with the sun on the horizon at T = 2.5);
// see docs/sun-and-sky.md for measured numbers.
//
// GPU: PreethamSky is laid out as seven vec4 so that it can be a member of a
// std140 uniform block (and std430 buffers) as is; its GLSL twin and
// skyRadiance live in shaders/sky.glsl, checked by tests/engine/sky_parity_test.cpp.
#pragma once

#include <cstddef>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "aperture/shaders/config.h"

namespace aal {

// Coefficients of the sky for one sun position and turbidity, computed once on
// the CPU (makePreethamSky) and evaluated per direction on the CPU or GPU.
// Default-constructed (all zero) it is a black sky.
// Channels: .x = Y (luminance), .y = x, .z = y (CIE 1931 chromaticity).
struct PreethamSky {
  glm::vec4 perezA{0.0f};  // Perez A for (Y, x, y); w: turbidity actually used
  glm::vec4 perezB{0.0f};  // Perez B; w: x of the midday CCT floor (middayCctFloor)
  glm::vec4 perezC{0.0f};  // Perez C; w: strength of that floor in [0, 1]
  glm::vec4 perezD{0.0f};  // Perez D (per radian); w: 0
  glm::vec4 perezE{0.0f};  // Perez E; w: 0
  // (Y_z fade / F_Y(0, theta_s) [kcd/m²], x_z / F_x(0, theta_s), y_z / F_y(0, theta_s),
  //  twilight fade in [0, 1])
  glm::vec4 zenith{0.0f};
  // xyz: unit direction to the sun used by the model (world frame, z up; the
  // true direction raised to the horizon when the sun is below it);
  // w: true sun elevation in radians.
  glm::vec4 sunDirection{0.0f};
};
// std140 and std430: seven vec4 at offsets 0, 16, ..., 96; 112 bytes, and an
// array stride of 112 (a multiple of 16).
static_assert(sizeof(PreethamSky) == 112, "PreethamSky must match shaders/sky.glsl");
static_assert(offsetof(PreethamSky, zenith) == 80 && offsetof(PreethamSky, sunDirection) == 96,
              "PreethamSky must match shaders/sky.glsl");

constexpr double kMinSkyTurbidity = 2.0;
constexpr double kMaxSkyTurbidity = 10.0;
// End of civil twilight: the sky is black when the sun is this far below the horizon.
constexpr double kCivilTwilightDeg = -6.0;
// Midday colour-temperature floor of the sky (file comment): the warmest CCT
// the sky shows by day, and the sun elevations over which it fades in.
constexpr double kMiddaySkyMinCctK = 6800.0;
constexpr double kMiddayFloorStartDeg = 30.0;
constexpr double kMiddayFloorFullDeg = 45.0;

// Sky luminance scale for the sun at elevationDeg (degrees, may be negative):
// the twilight rule of the file comment. 1 for elevation >= 0, 0 for <= -6°,
// continuous and decreasing in between.
double twilightFade(double elevationDeg);

// Coefficients for a sun in unit direction sunDir (world frame, z up; need not
// be above the horizon) and turbidity T (clamped to [2, 10]).
PreethamSky makePreethamSky(const glm::vec3& sunDir, double turbidity);

// max(y, y_D(x)): the CIE chromaticity y raised to the daylight locus where
// it lies below it (file comment). Twin of daylightLocusLift in shaders/sky.glsl.
float daylightLocusLift(float x, float y);

// x_D of the CIE daylight locus at correlated colour temperature cctK (CIE
// 15:2004 eq. 3.2, 4000-25000 K; clamped to that range).
double daylightLocusX(double cctK);

// Strength in [0, 1] of the midday CCT floor for the sun at elevationDeg:
// smoothstep from kMiddayFloorStartDeg (0) to kMiddayFloorFullDeg (1).
double middayCctFloorStrength(double elevationDeg);

// The sky chromaticity (x, y) with the midday floor of the file comment:
// where x > maxX, x moves towards maxX by `strength` and y by the change of
// the daylight locus between the two x (its offset from the locus kept);
// then y is lifted to the locus (daylightLocusLift). Unchanged where x <=
// maxX, apart from the lift. Twin of daylightChromaticity in shaders/sky.glsl.
glm::vec2 daylightChromaticity(float x, float y, float maxX, float strength);

// Sky radiance (photometric RGB, kcd/m²) seen looking along viewDir (any
// non-zero vector, world frame), its chromaticity floored and lifted (daylightChromaticity). Single
// precision, the same arithmetic as skyRadiance in shaders/sky.glsl. Angle from the sun gamma = 2
// atan(|v - s|, |v + s|), accurate for directions next to the sun.
glm::vec3 skyRadiance(const PreethamSky& sky, const glm::vec3& viewDir);

// Sky radiance averaged over the upper hemisphere with uniform solid-angle
// weight, (1 / 2 pi) * integral of L over the hemisphere: L_sky of
// docs/design.md §5. Midpoint rule on azimuthSteps x zenithSteps cells of equal
// solid angle (uniform in azimuth and in cos theta); the default 64 x 32 is
// within 0.5% of a 512 x 256 reference for sun elevations 0-90° (tested).
glm::vec3 averageSkyRadiance(const PreethamSky& sky, int azimuthSteps = 64, int zenithSteps = 32);

// Cosine-weighted average (1 / pi) * integral of L cos theta over the upper
// hemisphere: the radiance of a uniform sky that gives the same irradiance on
// a horizontal surface; pi times it is the diffuse horizontal illuminance
// (klx). Same quadrature as averageSkyRadiance.
glm::vec3 cosineWeightedSkyRadiance(const PreethamSky& sky, int azimuthSteps = 64,
                                    int zenithSteps = 32);

}  // namespace aal
