// Top-down shaded relief of a DEM (aal-relief, docs/relief.md): one value
// per output pixel in [0, 1], lit by the same terms as the renderer
// (terrain/light/shading.h, docs/rendering.md): the sun through the aperture's cap
// intersection and the sky fill, with the ambient transfer W of the
// containment-test obscurances (terrain/light/obscurance.h). CPU only; rows in
// parallel (oneTBB).
//
// Units: with irradiances normalised so that a surface facing an unoccluded
// sun gets (1 - k) and one under the full unoccluded sky gets k (k = sky
// weight), the value is direct + ambient of shadingTerms with albedo pi:
//   v = (1 - k) f max(0, N.C) + k sin^2(r) max(0, N.B) s W
// with f the visible sun fraction, C the centroid of its visible part, r and
// B the aperture, s the sky's share outside the sun's disk (shading.cpp).
// A horizontal surface under the full sky with the sun at elevation e
// (above its radius r_s) gets (1 - k) sin e + k cos r_s.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/units.h"

namespace aal {

enum class ReliefLighting {
  Sun,               // one sun (sunAzimuthDeg, sunElevationDeg) plus sky fill
  SkyOnly,           // the sky term alone: sin^2(r) max(0, N.B) W, 1 on open flat ground
  Multidirectional,  // suns at 225, 270, 315, 360 deg weighted by aspect, as gdaldem
};

struct ReliefSettings {
  // Output grid: the DEM's extent in outWidth x outHeight pixels (0: the
  // DEM's size, one pixel per texel). Pixel centres map to continuous texel
  // positions (i + 0.5) W / outWidth - 0.5. A pixel coarser than a texel
  // averages ceil(W / outWidth) x ceil(H / outHeight) points spread over it
  // (at 1/2 exactly the 2 x 2 texels' values); W (obscurance) is taken at
  // its centre.
  int outWidth = 0, outHeight = 0;
  ReliefLighting lighting = ReliefLighting::Sun;
  double sunAzimuthDeg = kDefaultSunAzimuthDeg;      // clockwise from north
  double sunElevationDeg = kDefaultSunElevationDeg;  // above the horizon
  double sunRadiusDeg = kSunAngularRadiusDeg;
  float skyWeight = 0.2f;                  // k in [0, 1]
  ShadingMode mode = ShadingMode::Approx;  // Approx or Exact
  ObscuranceSettings obscurance;           // enabled, radiusM (> 0), samples, steps are used
  float obscuranceAlbedo = 0.2f;           // the surroundings' albedo in W
  bool keepHeights = false;                // fill ReliefImage::heightM (colour relief)
  // Water: none unless asked. Texels at or below
  // waterLevelM, or flagged in waterMask (DEM-sized, non-zero = water), are
  // lit as a horizontal surface and flagged in ReliefImage::water.
  std::optional<double> waterLevelM;
  std::vector<uint8_t> waterMask;
};

struct ReliefImage {
  int width = 0, height = 0;
  std::vector<float> value;    // [0, 1]; NaN where the DEM has a void
  std::vector<float> heightM;  // bilinear DEM height at the pixel; empty unless keepHeights
  std::vector<uint8_t> water;  // 1 = water; empty when no water was asked for
  bool isVoid(size_t i) const { return value[i] != value[i]; }
};

// The weights of gdaldem hillshade -multidirectional (after Mark 1992,
// "Multidirectional, oblique-weighted, shaded-relief image of the Island of
// Hawaii", USGS OF 92-422): w(a) = cos^2(aspect - a) for the suns at a =
// 225, 270, 315, 360 deg, so the sun along the fall line counts most and the
// one across it not at all. gdaldem writes them as sin^2 of its
// mathematical aspect (counter-clockwise from east), which is the same. They
// sum to 2; the relief is sum w_i v_i / 2. Aspect in degrees clockwise from
// north, the direction the slope faces.
std::array<double, 4> multidirectionalWeights(double aspectDeg);
inline constexpr std::array<double, 4> kMultidirectionalAzimuthsDeg = {225, 270, 315, 360};

// An aperture map as RGBA 16-bit halves per texel, as the renderer uploads
// it (ApertureMapReader::readHalfRows): half the memory of ApertureMap.
struct HalfApertureMap {
  int width = 0, height = 0;
  std::vector<uint16_t> texels;  // 4 halves per texel: bent normal x, y, z; arc length
};
// Reads the whole map (a file or a tiled bake's folder) in bands of rows;
// errors as ApertureMapReader.
HalfApertureMap readHalfApertureMap(ApertureMapReader& reader);
HalfApertureMap toHalfApertureMap(const ApertureMap& map);

// The shaded relief of `field` with its aperture map (same size; checked by
// the caller with checkApertureMatchesDem). `progress` (may be empty) is
// called from the calling thread with the fraction done. Throws
// std::invalid_argument for a bad size or settings; honours interrupts
// (interrupt.h).
ReliefImage shadeRelief(const Heightfield& field, const ApertureMap& map,
                        const ReliefSettings& settings,
                        const std::function<void(double)>& progress = {});
ReliefImage shadeRelief(const Heightfield& field, const HalfApertureMap& map,
                        const ReliefSettings& settings,
                        const std::function<void(double)>& progress = {});

// The georeference of the DEM's extent cut into outWidth x outHeight pixels:
// the same outer corner, steps scaled.
GeoReference resampledGeoReference(const GeoReference& geo, int demWidth, int demHeight,
                                   int outWidth, int outHeight);

}  // namespace aal
