// Baking: the visible sky of every texel of a heightfield as an aperture
// (bent normal + cap arc length), plus the GIS sky-view factor. docs/design.md §3.
#pragma once

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/sky_illumination.h"
#include "aperture/terrain/height_view.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/horizon_map.h"

namespace aal {

struct FarField;  // far_horizon.h

enum class BakeMethod {
  Sweep,  // exact horizons per azimuth by line sweep, O(texels) per azimuth
  Rays,   // brute-force reference: rays over the hemisphere, marched texel by texel
};

struct BakeOptions {
  BakeMethod method = BakeMethod::Sweep;
  int azimuths = 64;           // sweep: number of azimuth slices, evenly spaced from east
  int rays = 1024;             // rays: rays per texel (stratified over the hemisphere)
  bool clampEdge = false;      // beyond the DEM edge: open sky (false) or flat at the edge height
  bool curvature = false;      // Earth curvature drop (R = 6371 km) with refraction
  double refraction = 0.13;    // refraction coefficient k: drop = (1 - k) t^2 / 2R
  double maxDistanceM = 0;     // 0 = the whole DEM counts
  bool skyViewFactor = false;  // also compute SVF = 1 - mean sin(max(h, 0))
  // Keep the aperture map (bent normals and arc lengths: 16 bytes per texel
  // of running sums). Off where only GIS rasters are wanted: the sweep then
  // sums only their terms, the result's aperture is empty, and a 1024² bake
  // of the sky-view factor takes about a fifth less time (docs/baking.md).
  // The ray bake always keeps it.
  bool apertureMap = true;
  // Also give the visible fraction of the sky (BakeResult::visibleFraction).
  bool visibleFraction = false;
  // Also compute topographic openness (openness.h), in degrees: positive
  // from the sweep's own horizons, negative from a second sweep over -z
  // (about as long again). Not with a far field; negative not with Earth
  // curvature.
  bool positiveOpenness = false;
  bool negativeOpenness = false;
  // Also compute the anisotropic sky-view factor with these weights, and
  // the diffuse illumination under a sky of this model
  // (sky_illumination.h), from the sweep's own horizons.
  bool anisotropicSkyViewFactor = false;
  Anisotropy anisotropy;
  bool skyIllumination = false;
  SkyModel skyModel = SkyModel::Overcast;
  // Also keep the horizon of horizonDirections azimuths (terrain/io/horizon_map.h):
  // the sweep's own horizons at k * 360 / horizonDirections degrees, so
  // `azimuths` must be a multiple of horizonDirections.
  bool horizons = false;
  int horizonDirections = kHorizonDirections;
  int horizonBits = kHorizonBits;  // 8 or 4 bits per code
  // A window's horizons beyond its halo, for a tiled bake without a max
  // distance (far_horizon.h): the near sweep walks the window's lines from
  // farField->options.nearReachM before it, the far field adds the rest.
  const FarField* farField = nullptr;
  // Called with the fraction done in [0, 1], from the calling thread.
  std::function<void(double)> progress;
  // When set and true, the bake stops and throws BakeCancelled.
  const std::atomic<bool>* cancel = nullptr;
};

class BakeCancelled : public std::runtime_error {
 public:
  BakeCancelled() : std::runtime_error("bake interrupted") {}
};

struct BakeResult {
  ApertureMap aperture;              // info filled except `source`
  std::vector<float> skyViewFactor;  // per texel in [0, 1] when requested, else empty
  // Per texel in [0, 1] when requested, else empty: the visible solid angle
  // over 2 pi, from the same sums as the map's arc length r (so 1 - cos r
  // up to r's rounding), with or without the map.
  std::vector<float> visibleFraction;
  // Per texel in degrees, in [0, 180], when requested, else empty; NaN on an
  // open edge, where an azimuth has no terrain ahead.
  std::vector<float> positiveOpenness, negativeOpenness;
  // Per texel when requested, else empty: the anisotropic sky-view factor
  // in [0, 1], the sky illumination, 1 on a plane under an open sky.
  std::vector<float> anisotropicSkyViewFactor, skyIllumination;
  HorizonMap horizons;  // when requested, else empty
};

constexpr double kEarthRadiusM = 6371000.0;

// Bakes the aperture map of `field` (heights in metres, cell sizes applied).
// Throws std::invalid_argument for options out of range.
BakeResult bakeApertures(const Heightfield& field, const BakeOptions& options);

// The header attributes a bake of `field` with these options carries, but
// `source` and `sourceChecksum`.
ApertureMapInfo bakeInfo(const Heightfield& field, const BakeOptions& options);

// Bakes only the texels of `window` (a tile of the DEM), with the whole
// DEM's geometry and horizons: equal bit for bit to the same texels of
// bakeApertures. `heights`: the whole DEM (a Heightfield), or a window of
// it (a HeightWindow) that holds the tile and what its sweeps read around
// it (tileHalo, tiled_bake.h). A partial window needs the sweep with a max
// distance (then only terrain near the tile is walked), or a far field
// (then the horizons beyond the near reach come from the far field's
// pyramid: close to, not equal to, the whole DEM's). The map has the
// window's size; its info describes the whole source, except that
// sourceChecksum is left empty (a tiled bake hashes the DEM once, not per
// tile).
BakeResult bakeApertureWindow(HeightView heights, const TexelWindow& window,
                              const BakeOptions& options);

}  // namespace aal
