// How well do encodings of the directional horizons (terrain/io/horizon_map.h)
// predict a low sun's visible fraction between their stored directions?
// A proxy for the horizon mode's error (docs/comparison.md, "Directional
// horizons for the sun") that needs no renderer: per texel, the direct
// light's Lambert-weighted visible fraction from an encoding against the
// one from the sweep's exact horizon in the sun's own azimuth, as an RMS
// over the DEM relative to that
// of baseline-lambert (no shadow), for sun elevations 3, 5, 8, 12, 20, 30
// and 45 degrees and the compass azimuths 1, 6, ..., 356 (never a stored
// direction; or the azimuths given).
//   bench_horizon_encoding_study DEM|fbm [COMPASS_AZIMUTH...]
// "fbm" is aal-synth --size 256 --amplitude 2500 --feature-size 64.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/bake_terrain.h"
#include "aperture/preprocess/horizon_sweep.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/terrain/synthetic.h"

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr int kFine = 64;  // the bake's azimuths, from which sector values come

struct Texel {
  float horizon[kFine];  // rad, the sweep's horizon at a * 2 pi / kFine
  float nx, ny, nz;
  float bent[3], apertureRad;  // the aperture of a 64-azimuth bake
};

// An encoding: what it stores of a texel's fine horizons (prepare, once per
// texel), and the horizon at azimuth phi from that.
struct Encoding {
  std::function<std::vector<float>(const Texel&)> prepare;
  std::function<float(const std::vector<float>&, double phi)> evaluate;
};

// Linear interpolation on a circle of n stored values.
float circularLinear(const float* values, int n, double phi) {
  double x = phi / (2 * kPi) * n;
  x -= n * std::floor(x / n);
  const int k0 = std::min(int(x), n - 1), k1 = (k0 + 1) % n;
  const double f = x - k0;
  return float((1 - f) * values[k0] + f * values[k1]);
}

// A quantiser from angle to angle through `levels` codes spaced as
// lo + (c / (levels - 1))^p (hi - lo).
struct PowerCode {
  int levels;
  double lo, hi, p;
  float operator()(float e) const {
    const double x = std::clamp((e - lo) / (hi - lo), 0.0, 1.0);
    const double c = std::round(std::pow(x, 1.0 / p) * (levels - 1));
    return float(lo + std::pow(c / (levels - 1), p) * (hi - lo));
  }
};

float eightBit(float e) {
  return aal::decodeHorizon(aal::encodeHorizon(e));
}

// n directions, each the sector statistic `stat` of the fine horizons
// within +-halfWidth fine steps, quantised by q, interpolated linearly.
Encoding sectorEncoding(int n, int halfWidth, std::function<float(const float*, int)> stat,
                        std::function<float(float)> q) {
  return Encoding{[=](const Texel& t) {
                    std::vector<float> stored(n);
                    const int step = kFine / n;
                    for (int k = 0; k < n; ++k) {
                      float window[kFine];
                      int m = 0;
                      for (int d = -halfWidth; d <= halfWidth; ++d) {
                        window[m++] = t.horizon[((k * step + d) % kFine + kFine) % kFine];
                      }
                      stored[k] = q(stat(window, m));
                    }
                    return stored;
                  },
                  [=](const std::vector<float>& stored, double phi) {
                    return circularLinear(stored.data(), n, phi);
                  }};
}

float centre(const float* w, int m) {
  return w[m / 2];
}
float maximum(const float* w, int m) {
  return *std::max_element(w, w + m);
}
float mean(const float* w, int m) {
  double s = 0;
  for (int i = 0; i < m; ++i) s += w[i];
  return float(s / m);
}

// The horizon's height above the tangent plane, quantised by q, linear
// between directions; the plane's elevation in the sun's azimuth added back.
float planeElevation(const Texel& t, double phi) {
  return float(std::atan(-(t.nx * std::cos(phi) + t.ny * std::sin(phi)) / t.nz));
}
Encoding planeEncoding(int n, std::function<float(float)> q) {
  return Encoding{
      [=](const Texel& t) {
        std::vector<float> stored(n);
        for (int k = 0; k < n; ++k) {
          const double phi = 2 * kPi * k / n;
          stored[k] = q(std::max(0.0f, t.horizon[k * kFine / n] - planeElevation(t, phi)));
        }
        std::vector<float> withNormal = stored;
        withNormal.push_back(t.nx), withNormal.push_back(t.ny), withNormal.push_back(t.nz);
        return withNormal;
      },
      [=](const std::vector<float>& stored, double phi) {
        Texel t;
        t.nx = stored[n], t.ny = stored[n + 1], t.nz = stored[n + 2];
        return circularLinear(stored.data(), n, phi) + planeElevation(t, phi);
      }};
}

// Interpolation of tangents instead of angles.
Encoding tangentEncoding(int n, std::function<float(float)> q) {
  return Encoding{[=](const Texel& t) {
                    std::vector<float> stored(n);
                    for (int k = 0; k < n; ++k) stored[k] = std::tan(q(t.horizon[k * kFine / n]));
                    return stored;
                  },
                  [=](const std::vector<float>& stored, double phi) {
                    return std::atan(circularLinear(stored.data(), n, phi));
                  }};
}

// Least-squares Fourier series of the fine horizons to `harmonics`, in floats.
Encoding fourierEncoding(int harmonics) {
  return Encoding{[=](const Texel& t) {
                    std::vector<float> c;
                    for (int h = 0; h <= harmonics; ++h) {
                      double a = 0, b = 0;
                      for (int k = 0; k < kFine; ++k) {
                        const double p = 2 * kPi * k / kFine;
                        a += t.horizon[k] * std::cos(h * p);
                        b += t.horizon[k] * std::sin(h * p);
                      }
                      const double scale = h == 0 ? 1.0 / kFine : 2.0 / kFine;
                      c.push_back(float(scale * a));
                      c.push_back(float(scale * b));
                    }
                    return c;
                  },
                  [=](const std::vector<float>& c, double phi) {
                    double value = 0;
                    for (int h = 0; h <= harmonics; ++h) {
                      value += c[2 * h] * std::cos(h * phi) + c[2 * h + 1] * std::sin(h * phi);
                    }
                    return float(value);
                  }};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s DEM|fbm [COMPASS_AZIMUTH...]\n", argv[0]);
    return 2;
  }
  try {
    aal::Heightfield field;
    if (std::string(argv[1]) == "fbm") {
      aal::SyntheticTerrainOptions s;
      s.amplitudeM = 2500;
      s.featureSizeTexels = 64;
      field = aal::makeSyntheticTerrain(s);
    } else {
      field = aal::loadDem(argv[1]);
    }
    const aal::BakeTerrain terrain = aal::prepareBakeTerrain(field);
    const size_t n = field.texelCount();
    std::vector<Texel> texels(n);
    for (int row = 0; row < field.height; ++row) {
      for (int col = 0; col < field.width; ++col) {
        Texel& t = texels[size_t(row) * field.width + col];
        const double sx = terrain.slopeEastAt(col, row), sy = terrain.slopeNorthAt(col, row);
        const double len = std::sqrt(sx * sx + sy * sy + 1);
        t.nx = float(-sx / len), t.ny = float(-sy / len), t.nz = float(1 / len);
      }
    }
    aal::BakeOptions bakeOptions;
    bakeOptions.azimuths = kFine;
    const aal::ApertureMap aperture = aal::bakeApertures(field, bakeOptions).aperture;
    for (size_t i = 0; i < n; ++i) {
      for (int c = 0; c < 3; ++c) texels[i].bent[c] = aperture.texels[4 * i + c];
      texels[i].apertureRad = aperture.texels[4 * i + 3];
    }
    const aal::HorizonSweepOptions sweep;
    const auto horizonsAt = [&](double phi, const std::function<void(size_t, float)>& store) {
      aal::sweepHorizons(terrain, phi, sweep, [&](size_t texel, double tangent) {
        store(texel, std::isfinite(tangent) ? float(std::atan(tangent)) : float(-kPi / 2));
      });
    };
    for (int a = 0; a < kFine; ++a) {
      horizonsAt(2 * kPi * a / kFine, [&](size_t i, float h) { texels[i].horizon[a] = h; });
    }
    std::vector<double> compass;
    for (int i = 2; i < argc; ++i) compass.push_back(std::stod(argv[i]));
    if (compass.empty()) {
      for (int a = 0; a < 360; a += 5) compass.push_back(a + 1.0);  // never a stored direction
    }

    const auto q8 = eightBit;
    const auto q4 = [](float e) { return aal::decodeHorizon(aal::encodeHorizon(e, 4), 4); };
    const auto id = [](float e) { return e; };
    const PowerCode sqrt4{16, -2 * kDeg, 90 * kDeg, 2.0};
    const PowerCode p15to30{16, -2 * kDeg, 30 * kDeg, 1.5};
    const PowerCode d15to45{16, 0, 45 * kDeg, 1.5};
    const PowerCode p18to30x8{8, -2 * kDeg, 30 * kDeg, 1.8};
    struct Named {
      const char* name;
      Encoding e;
    };
    const std::vector<Named> encodings = {
        {"8x8 (8 B)", sectorEncoding(8, 0, centre, q8)},
        {"8x8 tangents (8 B)", tangentEncoding(8, q8)},
        {"8x8 mean +-11 (8 B)", sectorEncoding(8, 2, mean, q8)},
        {"8x8 max +-6 (8 B)", sectorEncoding(8, 1, maximum, q8)},
        {"8x8 max +-11 (8 B)", sectorEncoding(8, 2, maximum, q8)},
        {"16x8 (16 B)", sectorEncoding(16, 0, centre, q8)},
        {"16x4 sqrt to 90 (8 B)", sectorEncoding(16, 0, centre, sqrt4)},
        {"16x4 p1.5 to 30 (8 B)", sectorEncoding(16, 0, centre, p15to30)},
        {"16x4, aal-bake's (8 B)", sectorEncoding(16, 0, centre, q4)},
        {"16x4 45 mean +-6 (8 B)", sectorEncoding(16, 1, mean, q4)},
        {"16x4 45 max +-6 (8 B)", sectorEncoding(16, 1, maximum, q4)},
        {"16x4 45 above plane", planeEncoding(16, d15to45)},
        {"16 floats above plane", planeEncoding(16, id)},
        {"32x3 p1.8 to 30 (12 B)", sectorEncoding(32, 0, centre, p18to30x8)},
        {"32 floats (128 B)", sectorEncoding(32, 0, centre, id)},
        {"Fourier 0-3 (7 floats)", fourierEncoding(3)},
        {"Fourier 0-7 (15 floats)", fourierEncoding(7)},
    };
    const float sunRadius = 0.004653f;
    const double elevations[] = {3, 5, 8, 12, 20, 30, 45};
    constexpr int kElevations = 7;
    std::printf("%-24s", "encoding \\ elevation");
    for (double e : elevations) std::printf(" %7.0f", e);
    std::printf("   (RMS of the Lambert-weighted sun fraction error / baseline-lambert's)\n");
    // The exact horizons in every sun azimuth, and baseline-lambert's error.
    std::vector<std::vector<float>> exact(compass.size(), std::vector<float>(n));
    for (size_t c = 0; c < compass.size(); ++c) {
      horizonsAt((90.0 - compass[c]) * kDeg, [&](size_t i, float h) { exact[c][i] = h; });
    }
    struct Sun {
      double phi, el, lx, ly, lz;
    };
    const auto sunOf = [&](size_t c, int e) {
      const double phi = (90.0 - compass[c]) * kDeg, el = elevations[e] * kDeg;
      return Sun{phi, el, std::cos(el) * std::cos(phi), std::cos(el) * std::sin(phi), std::sin(el)};
    };
    const auto lambertOf = [](const Texel& t, const Sun& s) {
      return std::max(0.0, t.nx * s.lx + t.ny * s.ly + t.nz * s.lz);
    };
    double lambertSum[kElevations] = {};
    for (size_t c = 0; c < compass.size(); ++c) {
      for (int e = 0; e < kElevations; ++e) {
        const Sun s = sunOf(c, e);
        for (size_t i = 0; i < n; ++i) {
          const double truth = aal::horizonSunFraction(float(s.el), exact[c][i], sunRadius);
          lambertSum[e] += std::pow((1 - truth) * lambertOf(texels[i], s), 2);
        }
      }
    }
    {  // approx: the sun's fraction from Oat's cap intersection
      double sum[kElevations] = {};
      const double sunCap = 2 * kPi * (1 - std::cos(double(sunRadius)));
      for (size_t c = 0; c < compass.size(); ++c) {
        for (int e = 0; e < kElevations; ++e) {
          const Sun s = sunOf(c, e);
          for (size_t i = 0; i < n; ++i) {
            const Texel& t = texels[i];
            const double lambert = lambertOf(t, s);
            if (lambert == 0) continue;
            const double truth = aal::horizonSunFraction(float(s.el), exact[c][i], sunRadius);
            const double dot = t.bent[0] * s.lx + t.bent[1] * s.ly + t.bent[2] * s.lz;
            const double cx = t.bent[1] * s.lz - t.bent[2] * s.ly,
                         cy = t.bent[2] * s.lx - t.bent[0] * s.lz,
                         cz = t.bent[0] * s.ly - t.bent[1] * s.lx;
            const double d = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot);
            const double f =
                aal::capIntersectionApprox(t.apertureRad, sunRadius, float(d)) / sunCap;
            sum[e] += std::pow((f - truth) * lambert, 2);
          }
        }
      }
      std::printf("%-24s", "approx (Oat's cap)");
      for (int e = 0; e < kElevations; ++e)
        std::printf(" %7.3f", std::sqrt(sum[e] / lambertSum[e]));
      std::printf("\n");
    }
    for (const Named& encoding : encodings) {
      std::vector<std::vector<float>> stored(n);
      for (size_t i = 0; i < n; ++i) stored[i] = encoding.e.prepare(texels[i]);
      double sum[kElevations] = {};
      for (size_t c = 0; c < compass.size(); ++c) {
        for (int e = 0; e < kElevations; ++e) {
          const Sun s = sunOf(c, e);
          for (size_t i = 0; i < n; ++i) {
            const double lambert = lambertOf(texels[i], s);
            if (lambert == 0) continue;
            const double truth = aal::horizonSunFraction(float(s.el), exact[c][i], sunRadius);
            const double f = aal::horizonSunFraction(
                float(s.el), encoding.e.evaluate(stored[i], s.phi), sunRadius);
            sum[e] += std::pow((f - truth) * lambert, 2);
          }
        }
      }
      std::printf("%-24s", encoding.name);
      for (int e = 0; e < kElevations; ++e)
        std::printf(" %7.3f", std::sqrt(sum[e] / lambertSum[e]));
      std::printf("\n");
      std::fflush(stdout);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
