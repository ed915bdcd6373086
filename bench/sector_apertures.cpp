#include "aperture/bench/sector_apertures.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/geometric.hpp>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/horizon_blocks.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/preprocess/sky_slice.h"
#include "aperture/terrain/light/caps.h"

namespace aal {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr int kMaxSectors = 16;

// Running sums of one texel's sector: the visible slice terms (bent vector,
// solid angle) and the occluded ones, as sky_slice.h lays them out.
struct SectorSums {
  std::array<double, 4> visible{};
  std::array<double, 4> occluded{};
};

// The cap Oat makes of a region: centred on its mean direction, with its
// solid angle. An empty region keeps radius 0 and points at `fallback`.
SectorCap capOf(const std::array<double, 4>& sums, const glm::dvec3& fallback) {
  SectorCap cap;
  const glm::dvec3 bent(sums[0], sums[1], sums[2]);
  const double length = glm::length(bent);
  const glm::dvec3 centre = length > 0.0 ? bent / length : fallback;
  cap.centre = glm::vec3(centre);
  const double fraction = std::clamp(sums[3] / kTwoPi, 0.0, 1.0);
  cap.radiusRad = static_cast<float>(std::acos(1.0 - fraction));
  return cap;
}

float capSunFraction(const SectorCap& cap, const glm::vec3& sun, float sunRadiusRad) {
  if (!(cap.radiusRad > 0.0f)) return 0.0f;
  const double d = std::atan2(double(glm::length(glm::cross(cap.centre, sun))),
                              double(glm::dot(cap.centre, sun)));
  const double sunArea = capArea(sunRadiusRad);
  if (!(sunArea > 0.0)) return d < cap.radiusRad ? 1.0f : 0.0f;
  return static_cast<float>(
      std::clamp(capIntersectionExact(cap.radiusRad, sunRadiusRad, d) / sunArea, 0.0, 1.0));
}

double sunAzimuth(const glm::vec3& sun) {
  return std::atan2(double(sun.y), double(sun.x));
}

// `fractionOf(sector)` looked up as `lookup` says for a sun in azimuth phi.
template <class Fraction>
float lookUp(int sectors, double phi, SectorLookup lookup, Fraction&& fractionOf) {
  switch (lookup) {
    case SectorLookup::Containing: return fractionOf(sectorOfAzimuth(phi, sectors));
    case SectorLookup::Blended: {
      // Sector centres at (k + 1/2) 2 pi / K.
      double t = phi / (kTwoPi / sectors) - 0.5;
      t -= sectors * std::floor(t / sectors);  // [0, K)
      const int k0 = std::min(static_cast<int>(t), sectors - 1);
      const float w = static_cast<float>(t - k0);
      return (1.0f - w) * fractionOf(k0) + w * fractionOf((k0 + 1) % sectors);
    }
    case SectorLookup::Union: {
      float best = 0.0f;
      for (int k = 0; k < sectors; ++k) best = std::max(best, fractionOf(k));
      return best;
    }
  }
  return 0.0f;
}

}  // namespace

int sectorOfAzimuth(double phiRad, int sectors) {
  double x = phiRad / kTwoPi * sectors;
  x -= sectors * std::floor(x / sectors);
  return std::min(static_cast<int>(x), sectors - 1);
}

SectorApertures bakeSectorApertures(const Heightfield& field, const BakeOptions& options,
                                    int sectors) {
  if (sectors < 1 || sectors > kMaxSectors) {
    throw std::invalid_argument("sectors must be in [1, 16]");
  }
  if (options.method != BakeMethod::Sweep || options.azimuths < 4 ||
      options.azimuths % sectors != 0) {
    throw std::invalid_argument("sector apertures need the sweep with a multiple of " +
                                std::to_string(sectors) + " azimuths");
  }
  if (field.width < 1 || field.height < 1 || field.z.size() != field.texelCount()) {
    throw std::invalid_argument("sector apertures: empty or partial heightfield");
  }
  const BakeTerrain terrain = prepareBakeTerrain(field);
  HorizonSweepOptions sweep;
  sweep.clampEdge = options.clampEdge;
  sweep.curvature = options.curvature ? (1.0 - options.refraction) / (2.0 * kEarthRadiusM) : 0.0;
  sweep.maxDistanceM = options.maxDistanceM;

  const size_t texels = field.texelCount();
  std::vector<SectorSums> sums(texels * size_t(sectors));
  const int perSector = options.azimuths / sectors;
  const double dPhi = kTwoPi / options.azimuths;
  for (int a = 0; a < options.azimuths; ++a) {
    const double phi = a * dPhi;
    const float cosPhi = static_cast<float>(std::cos(phi)),
                sinPhi = static_cast<float>(std::sin(phi));
    const float dPhiF = static_cast<float>(dPhi);
    const float cosPhiDPhi = static_cast<float>(std::cos(phi) * dPhi);
    const float sinPhiDPhi = static_cast<float>(std::sin(phi) * dPhi);
    // The slice on a boundary (a a multiple of perSector) is halved between
    // the sectors either side.
    const int upper = a / perSector;
    const bool boundary = a % perSector == 0;
    const int lower = boundary ? (upper + sectors - 1) % sectors : upper;
    const double weight = boundary ? 0.5 : 1.0;
    float open[4];  // the slice from the horizontal up
    skySliceTerms(open, 0.0f, dPhiF, cosPhiDPhi, sinPhiDPhi);
    sweepHorizons(terrain, phi, sweep, [&](size_t texel, double tanHorizon) {
      const float tanH = std::max(static_cast<float>(tanHorizon), kNoHorizonTangent);
      const float tanPlane = terrain.slopeEast(texel) * cosPhi + terrain.slopeNorth(texel) * sinPhi;
      const float tanTheta0 = std::max(tanH, tanPlane);
      float visible[4];
      skySliceTerms(visible, tanTheta0, dPhiF, cosPhiDPhi, sinPhiDPhi);
      for (const int k : {lower, upper}) {
        SectorSums& s = sums[texel * size_t(sectors) + size_t(k)];
        for (int c = 0; c < 4; ++c) {
          s.visible[c] += weight * visible[c];
          if (tanTheta0 > 0.0f) s.occluded[c] += weight * (open[c] - visible[c]);
        }
        if (!boundary) break;  // lower == upper: once
      }
    });
  }

  SectorApertures map;
  map.width = field.width;
  map.height = field.height;
  map.sectors = sectors;
  map.apertures.resize(sums.size());
  map.antiApertures.resize(sums.size());
  map.visibleSolidAngle.resize(sums.size());
  map.occludedSolidAngle.resize(sums.size());
  for (size_t i = 0; i < sums.size(); ++i) {
    const double mid = (static_cast<double>(i % size_t(sectors)) + 0.5) * kTwoPi / sectors;
    const glm::dvec3 horizontal(std::cos(mid), std::sin(mid), 0.0);
    map.apertures[i] = capOf(sums[i].visible, horizontal);
    map.antiApertures[i] = capOf(sums[i].occluded, horizontal);
    map.visibleSolidAngle[i] = static_cast<float>(sums[i].visible[3]);
    map.occludedSolidAngle[i] = static_cast<float>(sums[i].occluded[3]);
  }
  return map;
}

float sectorApertureSunFraction(const SectorApertures& map, size_t texel, const glm::vec3& sun,
                                float sunRadiusRad, SectorLookup lookup) {
  return lookUp(map.sectors, sunAzimuth(sun), lookup, [&](int k) {
    return capSunFraction(map.apertures[map.slot(texel, k)], sun, sunRadiusRad);
  });
}

float antiApertureSunFraction(const SectorApertures& map, size_t texel, const glm::vec3& sun,
                              float sunRadiusRad, SectorLookup lookup) {
  // The union of occluders hides the most: the smallest visible fraction.
  const auto visible = [&](int k) {
    return 1.0f - capSunFraction(map.antiApertures[map.slot(texel, k)], sun, sunRadiusRad);
  };
  if (lookup == SectorLookup::Union) {
    float least = 1.0f;
    for (int k = 0; k < map.sectors; ++k) least = std::min(least, visible(k));
    return least;
  }
  return lookUp(map.sectors, sunAzimuth(sun), lookup, visible);
}

}  // namespace aal
