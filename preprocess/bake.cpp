#include "aperture/preprocess/bake.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include <tbb/parallel_for.h>
#include <tbb/task_group.h>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/far_horizon.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/openness.h"
#include "aperture/preprocess/ray_bake.h"
#include "aperture/preprocess/slice_accumulator.h"
#include "aperture/terrain/huge_pages.h"

namespace aal {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void checkOptions(HeightView heights, const BakeOptions& o) {
  // The whole DEM, or a window of it inside the DEM.
  const Heightfield& dem = *heights.dem;
  const TexelWindow& held = heights.texels;
  const bool consistent = held.width >= 1 && held.height >= 1 && held.col >= 0 && held.row >= 0 &&
                          held.col + held.width <= dem.width &&
                          held.row + held.height <= dem.height &&
                          heights.z.size() == held.texelCount();
  if (dem.width < 1 || dem.height < 1 || !consistent) {
    throw std::invalid_argument("bake: empty or inconsistent heightfield");
  }
  if (o.azimuths < 4 || o.azimuths > 4096) {
    throw std::invalid_argument("azimuths must be in [4, 4096]");
  }
  if (o.rays < 16 || o.rays > 1 << 20) throw std::invalid_argument("rays must be in [16, 2^20]");
  if (!(o.maxDistanceM >= 0.0) || !std::isfinite(o.maxDistanceM)) {
    throw std::invalid_argument("max distance must be >= 0");
  }
  if (!(o.refraction >= 0.0 && o.refraction < 1.0)) {
    throw std::invalid_argument("refraction coefficient must be in [0, 1)");
  }
  if (o.horizons && !validHorizonDirections(o.horizonDirections)) {
    throw std::invalid_argument("horizon directions must be 4, 8, 12 or 16");
  }
  if (o.horizons && !validHorizonBits(o.horizonBits)) {
    throw std::invalid_argument("horizon codes must have 8 or 4 bits");
  }
  if (o.horizons && (o.method != BakeMethod::Sweep || o.azimuths % o.horizonDirections != 0)) {
    throw std::invalid_argument("directional horizons need the sweep with a multiple of " +
                                std::to_string(o.horizonDirections) + " azimuths");
  }
  const bool openness = o.positiveOpenness || o.negativeOpenness;
  if (openness && (o.method != BakeMethod::Sweep || o.farField)) {
    throw std::invalid_argument(
        "openness needs the sweep over the whole DEM or within a max distance (not a far field)");
  }
  if ((o.anisotropicSkyViewFactor || o.skyIllumination) && o.method != BakeMethod::Sweep) {
    throw std::invalid_argument(
        "the anisotropic sky-view factor and sky illumination need the sweep's horizons");
  }
  if (o.anisotropicSkyViewFactor &&
      !(o.anisotropy.minWeight >= 0 && o.anisotropy.minWeight <= 1 && o.anisotropy.exponent >= 0 &&
        std::isfinite(o.anisotropy.mainDirectionDeg))) {
    throw std::invalid_argument(
        "anisotropy: minimum weight must be in [0, 1], exponent >= 0, direction finite");
  }
  if (o.negativeOpenness && o.curvature) {
    throw std::invalid_argument("negative openness does not take Earth curvature");
  }
}

// Whether the bake sums the aperture map: asked for, or the ray
// reference's (which has no other sums).
bool keepsApertureMap(const BakeOptions& o) {
  return o.apertureMap || o.method != BakeMethod::Sweep;
}

void checkCancel(const BakeOptions& o) {
  if (o.cancel && o.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
}

// Sums the sky slices of every azimuth into `sums`, and the SVF terms and
// the horizon angles of openness where wanted; with `horizonCodes`, stores
// the horizons of the azimuths k * 2 pi / o.horizonDirections there (that
// many codes per texel).
class AzimuthSweeps {
 public:
  AzimuthSweeps(const BakeTerrain& terrain, const BakeOptions& o, float* sums, GisSums& gis,
                uint8_t* horizonCodes)
      : terrain_(terrain),
        o_(o),
        gis_(gis),
        sums_(terrain, o, sums, gis, horizonCodes),
        dPhi_(kTwoPi / o.azimuths) {
    sweep_.clampEdge = o.clampEdge;
    sweep_.curvature = o.curvature ? (1.0 - o.refraction) / (2.0 * kEarthRadiusM) : 0.0;
    sweep_.maxDistanceM = o.maxDistanceM;
    if (o.farField && o.maxDistanceM <= 0.0) {
      sweep_.windowReachM = o.farField->options.nearReachM;
      // The blocks of the pyramid this window's lines read, once per bake.
      if (o.farField->pyramid) {
        farWindow_.emplace(*o.farField, terrain);
        sweep_.windowReachM = farWindow_->walkReachM();
      }
    }
  }

  void run() const {
    // Without a distance limit azimuths a and a + n/2 are swept together
    // (sweepOpposedHorizonBlocks): one pass over the sums for both.
    // A far-field window's lines too, each azimuth from its own side.
    // So are a short limit's, which the block walk scans.
    const bool opposed =
        (sweep_.maxDistanceM <= 0.0 || detail::scansWithinLimit(terrain_, sweep_)) &&
        o_.azimuths % 2 == 0;
    const int passes = opposed ? o_.azimuths / 2 : o_.azimuths;
    for (int pass = 0; pass < passes; ++pass) {
      checkCancel(o_);
      const AzimuthSlice s = sliceOf(pass);
      if (!opposed) {
        sweepOne(s);
      } else {
        const AzimuthSlice opposite = sliceOf(pass + passes);
        if (!sweepOpposed(s, opposite)) {
          sweepOne(s);
          sweepOne(opposite);
        }
      }
      if (o_.progress) o_.progress(static_cast<double>(pass + 1) / passes);
    }
  }

  // Turns the GIS sums into their rasters, once they are packed at the
  // width of `window` (the terrain swept, at the window's own pitch).
  void finish(const BakeTerrain& window) const {
    if (!gis_.svf.empty()) finishSkyViewFactor(gis_.svf, o_.azimuths);
    if (!gis_.openness.empty()) finishOpenness(gis_.openness, o_.azimuths);
    if (!gis_.anisotropicSvf.empty()) finishSkyViewFactor(gis_.anisotropicSvf, weightSum());
    if (!gis_.skyIllumination.empty()) {
      finishSkyIllumination(window, gis_.skyIllumination, o_.azimuths, o_.skyModel);
    }
  }

 private:
  AzimuthSlice sliceOf(int a) const {
    const double phi = a * dPhi_, cosPhi = std::cos(phi), sinPhi = std::sin(phi);
    const bool stored = a * o_.horizonDirections % o_.azimuths == 0;
    return AzimuthSlice{phi,
                        static_cast<float>(cosPhi),
                        static_cast<float>(sinPhi),
                        static_cast<float>(dPhi_),
                        static_cast<float>(cosPhi * dPhi_),
                        static_cast<float>(sinPhi * dPhi_),
                        stored ? a * o_.horizonDirections / o_.azimuths : -1,
                        static_cast<float>(anisotropicWeight(o_.anisotropy, phi))};
  }

  // The anisotropic weights of all azimuths, summed as the slices hold them.
  double weightSum() const {
    double sum = 0;
    for (int a = 0; a < o_.azimuths; ++a) sum += sliceOf(a).anisotropicWeight;
    return sum;
  }

  // Both slices in one pass; false where their lines do not pair.
  bool sweepOpposed(const AzimuthSlice& s, const AzimuthSlice& opposite) const {
    return sweepOpposedHorizonBlocks(
        terrain_, s.phi, opposite.phi, sweep_,
        [&](const HorizonBlock& b) { sums_.addBlock(b, s, &opposite); },
        farWindow_ ? &*farWindow_ : nullptr);
  }

  void sweepOne(const AzimuthSlice& s) const {
    if (sweep_.windowReachM > 0.0) {
      sweepNearAndFar(s);
    } else if (sweep_.maxDistanceM > 0.0 && !detail::scansWithinLimit(terrain_, sweep_)) {
      sweepHorizonRuns(terrain_, s.phi, sweep_,
                       [&](const HorizonRun& run) { sums_.addRun(run, s); });
    } else {
      sweepHorizonBlocks(terrain_, s.phi, sweep_,
                         [&](const HorizonBlock& b) { sums_.addBlock(b, s, nullptr); });
    }
  }

  // A far-field bake's window: its lines walked from the near reach before
  // it, each starting with the far field's samples beyond (FarLineMarch).
  void sweepNearAndFar(const AzimuthSlice& s) const {
    sweepWindowHorizonBlocks(
        terrain_, s.phi, sweep_, [&](const HorizonBlock& b) { sums_.addBlock(b, s, nullptr); },
        &*farWindow_);
  }

  // The sums of the (weighted) SVF terms to the sky-view factor: 1 minus
  // their mean, `weights` the sum of the weights (the azimuths unweighted).
  static void finishSkyViewFactor(std::vector<float>& svf, double weights) {
    const float w = static_cast<float>(weights);
    tbb::parallel_for(size_t(0), svf.size(), [&](size_t i) { svf[i] = 1.0f - svf[i] / w; });
  }

  const BakeTerrain& terrain_;
  const BakeOptions& o_;
  GisSums& gis_;
  const SliceAccumulator sums_;
  const double dPhi_;
  HorizonSweepOptions sweep_;
  std::optional<FarFieldWindow> farWindow_;
};

// Turns the sums into unit bent normals and arc lengths, in place.
void finishApertures(const BakeTerrain& terrain, std::vector<float>& texels) {
  tbb::parallel_for(size_t(0), texels.size() / 4, [&](size_t i) {
    float* s = &texels[4 * i];
    double bx = s[0], by = s[1], bz = s[2];
    const double length = std::sqrt(bx * bx + by * by + bz * bz);
    if (length > 0.0) {
      bx /= length;
      by /= length;
      bz /= length;
    } else {  // nothing visible: fall back to the surface normal
      const double sx = terrain.slopeEast(i), sy = terrain.slopeNorth(i);
      const double n = std::sqrt(1.0 + sx * sx + sy * sy);
      bx = -sx / n;
      by = -sy / n;
      bz = 1.0 / n;
    }
    const double visible = std::clamp(s[3] / kTwoPi, 0.0, 1.0);
    s[0] = static_cast<float>(bx);
    s[1] = static_cast<float>(by);
    s[2] = static_cast<float>(bz);
    s[3] = static_cast<float>(std::acos(1.0 - visible));  // arc length of the cap
  });
}

// Visible solid angles, `stride` floats apart (4 in the aperture sums, 1
// in the GIS sums, where `shares` may be those sums: in place), to shares
// of the hemisphere, as finishApertures takes them before its arc lengths.
void visibleShares(const float* solidAngles, size_t stride, std::vector<float>& shares) {
  tbb::parallel_for(size_t(0), shares.size(), [&](size_t i) {
    shares[i] = static_cast<float>(std::clamp(solidAngles[stride * i] / kTwoPi, 0.0, 1.0));
  });
}

// Moves the rows of `v`, `rows` of `width` entries each, from `pitch`
// entries apart to `width` apart, in place, and drops the rest.
template <class T>
void packRows(std::vector<T>& v, size_t rows, size_t pitch, size_t width) {
  if (pitch == width || v.empty()) return;
  // Row r moves to before where row r + 1 lies: in order, no row is
  // overwritten before it has moved.
  for (size_t r = 1; r < rows; ++r) {
    std::memmove(v.data() + r * width, v.data() + r * pitch, width * sizeof(T));
  }
  v.resize(rows * width);
}

// Bakes the texels of the terrain's window; info.sourceChecksum is left to
// the caller.
BakeResult bakeWindow(const BakeTerrain& terrain, const BakeOptions& o) {
  // The running sums live in the output's own storage: 16 bytes per texel.
  // The sweep's rows of sums lie a few texels further apart than the
  // window's width where that width would make them share the cache's sets
  // (sumsPitch); they are packed to the width once summed.
  BakeTerrain summed = terrain;
  if (o.method == BakeMethod::Sweep) summed.pitch = sumsPitch(terrain.window.width);
  const size_t sums = summed.pitchedTexelCount();
  BakeResult result;
  ApertureMap& map = result.aperture;
  const bool apertureSums = keepsApertureMap(o);
  if (apertureSums) {
    map.width = terrain.window.width;
    map.height = terrain.window.height;
    assignOnHugePages(map.texels, sums * 4, 0.0f);
  }
  GisSums gis;
  if (o.visibleFraction && !apertureSums) assignOnHugePages(gis.visible, sums, 0.0f);
  if (o.skyViewFactor) assignOnHugePages(gis.svf, sums, 0.0f);
  if (o.positiveOpenness) assignOnHugePages(gis.openness, sums, 0.0f);
  if (o.anisotropicSkyViewFactor) assignOnHugePages(gis.anisotropicSvf, sums, 0.0f);
  if (o.skyIllumination) assignOnHugePages(gis.skyIllumination, sums, 0.0f);
  if (o.horizons) {
    result.horizons.width = terrain.window.width;
    result.horizons.height = terrain.window.height;
    result.horizons.directions = o.horizonDirections;
    result.horizons.bits = o.horizonBits;
    result.horizons.codes.assign(sums * size_t(o.horizonDirections), 0);
  }

  if (o.method == BakeMethod::Sweep) {
    // With negative openness the second sweep takes the second half of the
    // progress.
    BakeOptions first = o;
    if (o.negativeOpenness && o.progress) first.progress = [&](double f) { o.progress(0.5 * f); };
    const AzimuthSweeps sweeps(summed, first, apertureSums ? map.texels.data() : nullptr, gis,
                               o.horizons ? result.horizons.codes.data() : nullptr);
    sweeps.run();
    const size_t rows = size_t(terrain.window.height), pitch = size_t(summed.pitch),
                 width = size_t(terrain.window.width);
    packRows(map.texels, rows, 4 * pitch, 4 * width);
    for (std::vector<float>* g : gis.all()) packRows(*g, rows, pitch, width);
    const size_t directions = size_t(o.horizonDirections);
    packRows(result.horizons.codes, rows, directions * pitch, directions * width);
    sweeps.finish(terrain);
    result.positiveOpenness = std::move(gis.openness);
    result.anisotropicSkyViewFactor = std::move(gis.anisotropicSvf);
    result.skyIllumination = std::move(gis.skyIllumination);
    if (o.negativeOpenness) {
      BakeOptions second = o;
      if (o.progress) second.progress = [&](double f) { o.progress(0.5 + 0.5 * f); };
      result.negativeOpenness = negativeOpenness(terrain.heights, terrain.window, second);
    }
  } else {
    bakeRays(terrain, o, map.texels.data(), gis.svf);
  }
  result.skyViewFactor = std::move(gis.svf);
  if (o.visibleFraction && apertureSums) {
    result.visibleFraction.resize(map.texels.size() / 4);
    visibleShares(map.texels.data() + 3, 4, result.visibleFraction);
  } else if (o.visibleFraction) {
    result.visibleFraction = std::move(gis.visible);
    visibleShares(result.visibleFraction.data(), 1, result.visibleFraction);
  }
  finishApertures(terrain, map.texels);
  map.info = bakeInfo(*terrain.heights.dem, o);
  return result;
}

}  // namespace

ApertureMapInfo bakeInfo(const Heightfield& field, const BakeOptions& o) {
  ApertureMapInfo info;
  info.azimuths = o.method == BakeMethod::Sweep ? o.azimuths : 0;
  info.method = o.method == BakeMethod::Sweep ? "sweep" : "rays";
  if (o.farField && o.maxDistanceM <= 0.0) info.method = farFieldMethod(o.farField->options);
  info.cellSizeX = field.cellSizeXM;
  info.cellSizeY = field.cellSizeYM;
  info.zScale = field.zScale;
  info.sourceWidth = field.width;
  info.sourceHeight = field.height;
  info.edge = o.clampEdge ? "clamp" : "open";
  info.curvature = o.curvature;
  info.refraction = o.curvature ? o.refraction : 0.0;
  info.maxDistanceM = o.maxDistanceM;
  return info;
}

BakeResult bakeApertures(const Heightfield& field, const BakeOptions& o) {
  checkOptions(field, o);
  // The DEM's checksum (its rows hashed in parallel) is a task beside the
  // sweeps rather than a wait after them; only the map and the horizons
  // carry it.
  std::string checksum;
  tbb::task_group beside;
  if (keepsApertureMap(o) || o.horizons) {
    beside.run([&] { checksum = heightfieldChecksum(field); });
  }
  BakeResult result;
  try {
    result = bakeWindow(prepareBakeTerrain(field), o);
  } catch (...) {
    beside.wait();
    throw;
  }
  beside.wait();
  result.aperture.info.sourceChecksum = checksum;
  result.horizons.sourceChecksum = checksum;
  return result;
}

BakeResult bakeApertureWindow(HeightView heights, const TexelWindow& window, const BakeOptions& o) {
  checkOptions(heights, o);
  if (!window.covers(*heights.dem) &&
      (o.method != BakeMethod::Sweep || !(o.maxDistanceM > 0.0 || o.farField))) {
    throw std::invalid_argument("a bake window needs the sweep with a max distance or a far field");
  }
  // A window of the DEM must at least hold the tile; the halo around it is
  // the caller's (tileHalo, tiled_bake.h).
  if (!heights.texels.contains(window)) {
    throw std::invalid_argument("bake window outside the heights held");
  }
  return bakeWindow(prepareBakeTerrain(heights, window), o);
}

}  // namespace aal
