// The sun's visible fraction per texel by each way of storing a texel's sky
// (docs/comparison.md), against a brute-force reference: Oat's single
// aperture (approx and exact cap intersection), the directional horizons of
// 8 and 16 azimuths (terrain/io/horizon_map.h), and K sector apertures and
// anti-apertures (bench/sector_apertures.h) read three ways, and the
// single aperture less the anti-apertures. Prints, per sun and method, the
// mean |error| and the RMSE of the visible fraction over the texels that
// face the sun (N.L > 0: elsewhere the Lambert term hides the fraction).
// docs/comparison.md, "Several apertures per texel".
//
//   bench_sun_visibility DEM|fbm
//
// `fbm` is docs/comparison.md's rugged fBm, `aal-synth --size 256 --amplitude 2500
// --feature-size 64`, made in memory.
//
// Reference: the sun's disk (radius 0.004653 rad) is cut into 8 vertical
// strips; each strip sees the horizon marched brute force over the
// bilinear surface in its own azimuth (steps of a quarter cell, finer near
// the texel; open sky beyond the edge; the surface's tangent plane as the
// bake's lower bound, docs/design.md §3), and the strip's area above it is
// integrated numerically.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <numbers>
#include <string>
#include <vector>

#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>

#include "aperture/bench/sector_apertures.h"
#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/ray_bake.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/synthetic.h"

namespace {

using namespace aal;

constexpr double kPi = std::numbers::pi;
constexpr double kSunRadiusRad = 0.004653;
constexpr int kStrips = 8;         // vertical strips of the sun's disk
constexpr int kStripSamples = 16;  // midpoints per strip for its area
constexpr int kAzimuths = 64;      // of every bake here
const double kCompassAzimuthsDeg[] = {20, 60, 135, 240, 247.5, 250, 290};
const double kElevationsDeg[] = {3, 5, 8, 12};
const int kSectorCounts[] = {2, 4, 8};

// The steepest tangent from texel (col, row) to the bilinear surface in
// azimuth phi (counter-clockwise from east), or -1e30 when nothing lies
// ahead. Positions as the bake's (BakeTerrain), so geographic grids too.
double marchedHorizonTangent(const BakeTerrain& terrain, int col, int row, double phi,
                             double zMax) {
  const Heightfield& f = *terrain.heights.dem;
  const double ux = std::cos(phi), uy = std::sin(phi);
  const double x = terrain.x(col, row), y = terrain.y(row), z0 = f.at(col, row);
  const double step = 0.25 * std::min(terrain.cellY, terrain.rowCellX[f.height / 2]);
  const double rowCentre = 0.5 * (f.height - 1);
  double best = -1e30;
  for (double s = step / 64;; s += std::min(step, s)) {
    if ((zMax - z0) / s <= best) return best;  // nothing farther can rise above it
    const double px = x + ux * s, py = y + uy * s;
    const double r = rowCentre - py / terrain.cellY;
    const double rowClamped = std::clamp(r, 0.0, double(f.height - 1));
    const double cellX = terrain.rowCellX[static_cast<size_t>(std::lround(rowClamped))];
    const double c = terrain.centreCol + px / cellX;
    if (r < 0 || r > f.height - 1 || c < 0 || c > f.width - 1) return best;
    best = std::max(best, (f.bilinearHeight(c, r) - z0) / s);
  }
}

// Area of the strip [x0, x1] of a disk of radius rs (centred at 0) above
// height y (all in radians of the sky), by the midpoint rule.
double stripAreaAbove(double x0, double x1, double rs, double y) {
  double area = 0;
  const double dx = (x1 - x0) / kStripSamples;
  for (int i = 0; i < kStripSamples; ++i) {
    const double x = x0 + (i + 0.5) * dx;
    const double c = std::sqrt(std::max(0.0, rs * rs - x * x));
    area += std::clamp(c - std::max(y, -c), 0.0, 2 * c) * dx;
  }
  return area;
}

// The part of the sun's disk whose rays escape the terrain (rayEscapes, the
// reference bake's march), on a stratified grid of kDiskGrid^2 points of its
// bounding square that fall inside the disk: the strip reference's check.
constexpr int kDiskGrid = 8;
double marchedDiskFraction(const BakeTerrain& terrain, int col, int row, const glm::dvec3& sun,
                           double zMax) {
  const glm::dvec3 right = glm::normalize(glm::cross(sun, glm::dvec3(0, 0, 1)));
  const glm::dvec3 up = glm::cross(right, sun);
  BakeOptions open;
  int inside = 0, escaped = 0;
  for (int a = 0; a < kDiskGrid; ++a) {
    for (int b = 0; b < kDiskGrid; ++b) {
      const double x = -1 + (2 * a + 1.0) / kDiskGrid, y = -1 + (2 * b + 1.0) / kDiskGrid;
      if (x * x + y * y > 1) continue;
      ++inside;
      const glm::dvec3 d = glm::normalize(sun + kSunRadiusRad * (x * right + y * up));
      const double dir[3] = {d.x, d.y, d.z};
      escaped += rayEscapes(terrain, open, terrain.x(col, row), terrain.y(row),
                            terrain.heights.at(col, row), dir, zMax);
    }
  }
  return double(escaped) / inside;
}

struct Sun {
  double compassDeg, elevationDeg;
  double phi, elevation;  // rad, phi counter-clockwise from east
  glm::vec3 direction;
};

Sun makeSun(double compassDeg, double elevationDeg) {
  Sun s{compassDeg, elevationDeg, (90.0 - compassDeg) * kPi / 180, elevationDeg * kPi / 180, {}};
  s.direction = glm::vec3(std::cos(s.elevation) * std::cos(s.phi),
                          std::cos(s.elevation) * std::sin(s.phi), std::sin(s.elevation));
  return s;
}

struct Method {
  std::string name;
  int bytesPerTexel;  // beyond heights, slopes and the single aperture
  double sumAbs = 0, sumSquare = 0;
  double totalAbs = 0, totalSquare = 0;  // over all suns
};

Heightfield ruggedFbm() {
  SyntheticTerrainOptions s;
  s.width = s.height = 256;
  s.cellSizeM = 30;
  s.amplitudeM = 2500;
  s.featureSizeTexels = 64;
  return makeSyntheticTerrain(s);
}

int run(const std::string& dem) {
  const Heightfield field = dem == "fbm" ? ruggedFbm() : loadDem(dem);
  const BakeTerrain terrain = prepareBakeTerrain(field);
  const double zMax = *std::max_element(field.z.begin(), field.z.end());
  const size_t texels = field.texelCount();

  // The reference's strip integral against the closed form for a straight
  // horizon (horizonSunFraction): the reference's own error.
  double worstStraight = 0;
  for (double y = -1.2; y <= 1.2; y += 0.01) {
    double area = 0, total = 0;
    for (int j = 0; j < kStrips; ++j) {
      const double x0 = kSunRadiusRad * (-1 + 2.0 * j / kStrips);
      const double x1 = kSunRadiusRad * (-1 + 2.0 * (j + 1) / kStrips);
      area += stripAreaAbove(x0, x1, kSunRadiusRad, y * kSunRadiusRad);
      total += stripAreaAbove(x0, x1, kSunRadiusRad, -1);
    }
    worstStraight = std::max(worstStraight,
                             std::abs(area / total - horizonSunFraction(0, float(y * kSunRadiusRad),
                                                                        float(kSunRadiusRad))));
  }
  std::printf("# reference strip integral vs closed form, straight horizon: worst %.2e\n",
              worstStraight);

  BakeOptions o;
  o.azimuths = kAzimuths;
  o.horizons = true;
  const BakeResult bake8 = bakeApertures(field, o);
  o.horizonDirections = 16;
  const BakeResult bake16 = bakeApertures(field, o);
  o.horizons = false;
  std::vector<SectorApertures> sectors;
  for (const int k : kSectorCounts) sectors.push_back(bakeSectorApertures(field, o, k));

  std::vector<Method> methods = {
      {"approx (single cap)", 0}, {"exact (single cap)", 0}, {"horizon 8", 8}, {"horizon 16", 16}};
  const char* lookups[] = {"containing", "blended", "union"};
  for (const int k : kSectorCounts) {
    for (const char* l : lookups) {
      methods.push_back({"apertures K=" + std::to_string(k) + " " + l, 4 * k});
    }
  }
  for (const int k : kSectorCounts) {
    for (const char* l : lookups) {
      methods.push_back({"anti-apertures K=" + std::to_string(k) + " " + l, 4 * k});
    }
  }
  // Oat's two ideas together: the sun through the single aperture and not
  // behind the anti-aperture of its sector (the product of the two
  // fractions, which for a sun this small are nearly always 0 or 1).
  for (const int k : kSectorCounts) {
    methods.push_back({"aperture and anti-apertures K=" + std::to_string(k), 4 * k});
  }
  const SectorLookup lookupOf[] = {SectorLookup::Containing, SectorLookup::Blended,
                                   SectorLookup::Union};

  std::printf(
      "# %s, %d x %d texels; per sun: mean |error|, RMSE of the visible fraction over "
      "texels facing the sun\n",
      dem.c_str(), field.width, field.height);
  std::printf("compass,elevation,method,bytes,texels,mean_abs,rmse\n");
  std::vector<float> reference(texels), estimate(texels * methods.size());
  std::vector<uint8_t> facing(texels);
  int suns = 0;
  for (const double compass : kCompassAzimuthsDeg) {
    for (const double elevationDeg : kElevationsDeg) {
      const Sun sun = makeSun(compass, elevationDeg);
      ++suns;
      tbb::parallel_for(0, field.height, [&](int row) {
        for (int col = 0; col < field.width; ++col) {
          const size_t i = field.index(col, row);
          const float sx = terrain.slopeEast(i), sy = terrain.slopeNorth(i);
          const glm::vec3 normal = glm::normalize(glm::vec3(-sx, -sy, 1.0f));
          facing[i] = glm::dot(normal, sun.direction) > 0.0f;
          if (!facing[i]) continue;
          double area = 0, total = 0;
          for (int j = 0; j < kStrips; ++j) {
            const double x0 = kSunRadiusRad * (-1 + 2.0 * j / kStrips);
            const double x1 = kSunRadiusRad * (-1 + 2.0 * (j + 1) / kStrips);
            // Strip centre's azimuth: left of the disk is counter-clockwise.
            const double phi = sun.phi - 0.5 * (x0 + x1) / std::cos(sun.elevation);
            const double tanPlane = sx * std::cos(phi) + sy * std::sin(phi);
            const double tanH =
                std::max(marchedHorizonTangent(terrain, col, row, phi, zMax), tanPlane);
            area += stripAreaAbove(x0, x1, kSunRadiusRad, std::atan(tanH) - sun.elevation);
            total += stripAreaAbove(x0, x1, kSunRadiusRad, -1);
          }
          reference[i] = static_cast<float>(area / total);

          float* e = &estimate[i * methods.size()];
          const float* a = &bake8.aperture.texels[4 * i];
          const glm::vec3 bent(a[0], a[1], a[2]);
          const float d = std::atan2(glm::length(glm::cross(bent, sun.direction)),
                                     glm::dot(bent, sun.direction));
          const double sunArea = capArea(kSunRadiusRad);
          e[0] = std::clamp(float(capIntersectionApprox(a[3], float(kSunRadiusRad), d) / sunArea),
                            0.0f, 1.0f);
          e[1] =
              float(std::clamp(capIntersectionExact(a[3], kSunRadiusRad, d) / sunArea, 0.0, 1.0));
          const auto fromHorizons = [&](const HorizonMap& h) {
            return horizonSunFraction(
                float(sun.elevation),
                horizonAtAzimuth(h.texel(col, row), h.directions, float(sun.phi)),
                float(kSunRadiusRad));
          };
          e[2] = fromHorizons(bake8.horizons);
          e[3] = fromHorizons(bake16.horizons);
          size_t m = 4;
          for (const SectorApertures& s : sectors) {
            for (const SectorLookup l : lookupOf) {
              e[m++] = sectorApertureSunFraction(s, i, sun.direction, float(kSunRadiusRad), l);
            }
          }
          for (const SectorApertures& s : sectors) {
            for (const SectorLookup l : lookupOf) {
              e[m++] = antiApertureSunFraction(s, i, sun.direction, float(kSunRadiusRad), l);
            }
          }
          for (const SectorApertures& s : sectors) {
            e[m++] = e[1] * antiApertureSunFraction(s, i, sun.direction, float(kSunRadiusRad),
                                                    SectorLookup::Containing);
          }
        }
      });
      // The strip reference against rays over the disk at every 61st texel
      // facing the sun: the two differ where a ray grazes the surface near
      // the texel and by the 8 x 8 grid's coarseness.
      double rayDifference = 0;
      size_t rayTexels = 0;
      for (size_t i = 0; i < texels; i += 61) {
        if (!facing[i]) continue;
        const int col = static_cast<int>(i % size_t(field.width));
        const int row = static_cast<int>(i / size_t(field.width));
        rayDifference += std::abs(
            marchedDiskFraction(terrain, col, row, glm::dvec3(sun.direction), zMax) - reference[i]);
        ++rayTexels;
      }
      std::printf(
          "# %g/%g: strip reference vs rays over the disk: mean |difference| %.4f (%zu "
          "texels)\n",
          compass, elevationDeg, rayDifference / double(rayTexels), rayTexels);
      size_t count = 0;
      for (Method& method : methods) method.sumAbs = method.sumSquare = 0;
      for (size_t i = 0; i < texels; ++i) {
        if (!facing[i]) continue;
        ++count;
        for (size_t m = 0; m < methods.size(); ++m) {
          const double error = double(estimate[i * methods.size() + m]) - reference[i];
          methods[m].sumAbs += std::abs(error);
          methods[m].sumSquare += error * error;
        }
      }
      for (Method& method : methods) {
        const double meanAbs = method.sumAbs / double(count);
        const double rmse = std::sqrt(method.sumSquare / double(count));
        method.totalAbs += meanAbs;
        method.totalSquare += rmse;
        std::printf("%g,%g,%s,%d,%zu,%.4f,%.4f\n", compass, elevationDeg, method.name.c_str(),
                    method.bytesPerTexel, count, meanAbs, rmse);
      }
      std::fflush(stdout);
    }
  }
  std::printf("# averages over the %d suns: method, bytes per texel, mean |error|, RMSE\n", suns);
  for (const Method& method : methods) {
    std::printf("# %-32s %2d B  %.4f  %.4f\n", method.name.c_str(), method.bytesPerTexel,
                method.totalAbs / suns, method.totalSquare / suns);
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DEM|fbm\n", argv[0]);
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const aal::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
