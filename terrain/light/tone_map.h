// From linear HDR radiance (photometric RGB, kcd/m²; atmosphere.h) to display
// sRGB: exposure, a filmic curve, and the sRGB transfer function.
//
//   display = srgbEncode(clamp(filmic(max(hdr, 0) * exposure), 0, 1))   per channel
//
// - Exposure is a linear multiplier (1 / kcd/m²) on scene radiance.
//   exposureFromEv100 gives it from a camera exposure value;
//   exposureForMiddleGrey and autoExposure pick it from the scene.
// - filmic(x) = h(x) / h(W) with Hable's curve
//     h(x) = (x (A x + C B) + D E) / (x (A x + B) + D F) - E / F
//   (John Hable, "Uncharted 2: HDR Lighting", GDC 2010, and "Filmic Tonemapping
//   Operators", 2010), A..F and the linear white point W = 11.2 in
//   shaders/config.h (AAL_FILMIC_*), evaluated over one denominator so that
//   h(0) = 0 exactly. filmic(0) = 0, filmic(W) = 1, monotonic, with a toe and
//   a shoulder; inputs >= W are white.
// - srgbEncode: IEC 61966-2-1, 12.92 c for c <= 0.0031308, else
//   1.055 c^(1/2.4) - 0.055.
// The GLSL twins are in shaders/tone_map.glsl, checked by
// tests/engine/sky_parity_test.cpp.
#pragma once

#include <glm/vec3.hpp>

namespace aal {

// Display-linear middle grey (18% reflectance), which srgbEncode turns into 0.461.
constexpr float kMiddleGrey = 0.18f;

// Albedo of the "average terrain" that autoExposure puts at middle grey.
constexpr float kReferenceTerrainAlbedo = 0.2f;

// Hable's filmic curve normalised to 1 at the white point: [0, W] -> [0, 1];
// inputs are clamped to [0, W] first (above W it is white).
float filmicCurve(float x);

// Inverse of filmicCurve on [0, 1): the x >= 0 with filmicCurve(x) = y
// (closed form: the curve is a ratio of quadratics). y is clamped to
// [0, 1 - 1e-6].
float inverseFilmicCurve(float y);

// sRGB transfer function (IEC 61966-2-1) of a linear value in [0, 1].
float linearToSrgb(float linear);

// Display sRGB in [0, 1] for linear HDR radiance (kcd/m²) and an exposure
// multiplier (1 / kcd/m²). Negative inputs count as 0.
glm::vec3 toneMap(const glm::vec3& linearHdr, float exposure);

// Exposure multiplier for a camera exposure value at ISO 100: 1 / L_max with
// the saturation-based L_max = 1.2 * 2^EV100 cd/m² (ISO 12232; Lagarde & de
// Rousiers 2014, "Moving Frostbite to PBR", §5.1), i.e. 1000 / (1.2 * 2^EV100)
// in our kcd/m² units. Sunny-16 daylight is EV100 ~ 15.
float exposureFromEv100(float ev100);

// Exposure that maps a scene luminance (kcd/m², > 0) to display middle grey:
// inverseFilmicCurve(kMiddleGrey) / luminance. Luminances below 1e-6 kcd/m²
// count as 1e-6 so that a black scene gets a finite exposure.
float exposureForMiddleGrey(float sceneLuminance);

// Luminance (kcd/m²) of flat, open, horizontal Lambertian terrain of the given
// albedo under the sun and sky, as the renderer shades it (docs/design.md §5
// with N = B = up, full aperture, f = 1, W = 1):
//   albedo / pi * (Y(E_sun) max(0, sin elevation) + pi Y(L_sky)).
// sunIrradiance in klx (atmosphere.h sunIrradiance), skyRadiance = L_sky in
// kcd/m² (sky_model.h averageSkyRadiance).
float flatTerrainLuminance(const glm::vec3& sunIrradiance, double sunElevationDeg,
                           const glm::vec3& skyRadiance, float albedo = kReferenceTerrainAlbedo);

// Exposure that puts that terrain at middle grey:
// exposureForMiddleGrey(flatTerrainLuminance(...)). Call it with the lighting
// of a clear-day noon (e.g. the sun at solar noon of the rendered date and
// place) and keep the result for a whole time-of-day series, so that dawn,
// dusk and night come out darker than noon rather than all grey. At T = 2.5
// with the sun at 60° it is ~0.07 per kcd/m² (docs/sun-and-sky.md).
float autoExposure(const glm::vec3& sunIrradiance, double sunElevationDeg,
                   const glm::vec3& skyRadiance, float albedo = kReferenceTerrainAlbedo);

}  // namespace aal
