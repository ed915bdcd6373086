#include "aperture/terrain/reference/relief.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <Imath/half.h>

#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/light/obscurance_samples.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

// Normal from height differences over one texel either side, one-sided at
// the DEM's edges (gdaldem's -compute_edges, not the renderer's clamped
// half difference), in the world frame (x east, y north, z up).
glm::vec3 surfaceNormal(const Heightfield& field, double col, double row) {
  const double xa = std::max(0.0, col - 1), xb = std::min(field.width - 1.0, col + 1);
  const double ya = std::max(0.0, row - 1), yb = std::min(field.height - 1.0, row + 1);
  const int nearestRow = std::clamp(static_cast<int>(std::lround(row)), 0, field.height - 1);
  const double dx = field.cellSizeXAtRow(nearestRow), dy = field.cellSizeYM;
  const double east =
      xb > xa ? (field.bilinearHeight(xb, row) - field.bilinearHeight(xa, row)) / ((xb - xa) * dx)
              : 0.0;
  // Rows grow southwards: north is towards ya.
  const double north =
      yb > ya ? (field.bilinearHeight(col, ya) - field.bilinearHeight(col, yb)) / ((yb - ya) * dy)
              : 0.0;
  return glm::normalize(glm::vec3(glm::dvec3(-east, -north, 1.0)));
}

// Texel (c, r) of an aperture map as (bent normal, arc length).
struct FloatTexels {
  const ApertureMap& map;
  glm::vec4 operator()(int c, int r) const {
    const float* t = &map.texels[4 * (static_cast<size_t>(r) * map.width + c)];
    return glm::vec4(t[0], t[1], t[2], t[3]);
  }
};
struct HalfTexels {
  const HalfApertureMap& map;
  glm::vec4 operator()(int c, int r) const {
    const uint16_t* t = &map.texels[4 * (static_cast<size_t>(r) * map.width + c)];
    glm::vec4 v;
    for (int k = 0; k < 4; ++k) {
      Imath::half h;
      h.setBits(t[k]);
      v[k] = static_cast<float>(h);
    }
    return v;
  }
};

// Bilinear bent normal (renormalised) and arc length at a texel position.
template <class Texels>
void sampleAperture(const Texels& at, int width, int height, double col, double row,
                    glm::vec3& bent, float& arc) {
  col = std::clamp(col, 0.0, width - 1.0);
  row = std::clamp(row, 0.0, height - 1.0);
  const int c0 = std::min(static_cast<int>(col), std::max(width - 2, 0));
  const int r0 = std::min(static_cast<int>(row), std::max(height - 2, 0));
  const int c1 = std::min(c0 + 1, width - 1), r1 = std::min(r0 + 1, height - 1);
  const float tc = static_cast<float>(col - c0), tr = static_cast<float>(row - r0);
  const glm::vec4 top = at(c0, r0) + (at(c1, r0) - at(c0, r0)) * tc;
  const glm::vec4 bottom = at(c0, r1) + (at(c1, r1) - at(c0, r1)) * tc;
  const glm::vec4 v = top + (bottom - top) * tr;
  const glm::vec3 b(v);
  const float length = glm::length(b);
  bent = length > 1e-6f ? b / length : glm::vec3(0, 0, 1);
  arc = v.w;
}

float aspectDeg(const glm::vec3& normal) {
  // The horizontal part of the normal points downslope, where the slope faces.
  const double a = std::atan2(normal.x, normal.y) / kRadiansPerDegree;
  return static_cast<float>(a < 0 ? a + 360 : a);
}

// 4x4 box filter of W over the interleaving pattern (Keller & Heidrich,
// "Interleaved Sampling", 2001; docs/obscurance.md), voids
// left out.
void boxFilter4(std::vector<float>& w, const std::vector<uint8_t>& voids, int width, int height) {
  std::vector<float> out(w.size());
  tbb::parallel_for(0, height, [&](int y) {
    for (int x = 0; x < width; ++x) {
      const size_t i = static_cast<size_t>(y) * width + x;
      double sum = 0;
      int n = 0;
      for (int dy = -2; dy <= 1; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= height) continue;
        for (int dx = -2; dx <= 1; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= width) continue;
          const size_t j = static_cast<size_t>(yy) * width + xx;
          if (voids[j]) continue;
          sum += w[j];
          ++n;
        }
      }
      out[i] = n > 0 ? static_cast<float>(sum / n) : w[i];
    }
  });
  w.swap(out);
}

}  // namespace

std::array<double, 4> multidirectionalWeights(double aspectDegrees) {
  std::array<double, 4> w{};
  for (size_t i = 0; i < w.size(); ++i) {
    const double c = std::cos(radians(aspectDegrees - kMultidirectionalAzimuthsDeg[i]));
    w[i] = c * c;
  }
  return w;
}

GeoReference resampledGeoReference(const GeoReference& geo, int demWidth, int demHeight,
                                   int outWidth, int outHeight) {
  GeoReference out = geo;
  out.stepX = geo.stepX * demWidth / outWidth;
  out.stepY = geo.stepY * demHeight / outHeight;
  // The outer corner stays: origin is a pixel centre, half a step inside.
  out.originX = geo.originX - 0.5 * geo.stepX + 0.5 * out.stepX;
  out.originY = geo.originY + 0.5 * geo.stepY - 0.5 * out.stepY;
  return out;
}

namespace {

template <class Texels>
ReliefImage shadeWith(const Heightfield& field, const Texels& texels, const ReliefSettings& s,
                      const std::function<void(double)>& progress) {
  if (!(s.skyWeight >= 0 && s.skyWeight <= 1) ||
      (s.mode != ShadingMode::Approx && s.mode != ShadingMode::Exact)) {
    throw std::invalid_argument("shadeRelief: sky weight in [0, 1], mode approx or exact");
  }
  if (!s.waterMask.empty() && s.waterMask.size() != field.texelCount()) {
    throw std::invalid_argument("shadeRelief: the water mask must have the DEM's size");
  }
  ReliefImage image;
  image.width = s.outWidth > 0 ? s.outWidth : field.width;
  image.height = s.outHeight > 0 ? s.outHeight : field.height;
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  image.value.assign(pixels, 0.0f);
  if (s.keepHeights) image.heightM.assign(pixels, 0.0f);
  const bool anyWater = s.waterLevelM.has_value() || !s.waterMask.empty();
  if (anyWater) image.water.assign(pixels, 0);

  const double scaleX = double(field.width) / image.width;
  const double scaleY = double(field.height) / image.height;

  // Suns and their weights (the weights of Multidirectional depend on the
  // aspect and are set per pixel).
  std::vector<glm::vec3> suns;
  if (s.lighting == ReliefLighting::Multidirectional) {
    for (const double a : kMultidirectionalAzimuthsDeg) {
      suns.push_back(sunDirection(a, s.sunElevationDeg));
    }
  } else if (s.lighting == ReliefLighting::Sun) {
    suns.push_back(sunDirection(s.sunAzimuthDeg, s.sunElevationDeg));
  }

  ShadingInputs base;
  base.albedo = glm::vec3(static_cast<float>(kPi));  // albedo / pi = 1
  base.sunRadiusRad = static_cast<float>(radians(s.sunRadiusDeg));
  base.sunIrradiance = glm::vec3(1.0f - s.skyWeight);
  base.skyRadiance = glm::vec3(static_cast<float>(s.skyWeight / kPi));
  if (s.lighting == ReliefLighting::SkyOnly) {
    // No sun: its cap takes nothing from the sky, the sky has full weight.
    base.sunRadiusRad = 0;
    base.sunIrradiance = glm::vec3(0.0f);
    base.skyRadiance = glm::vec3(static_cast<float>(1.0 / kPi));
  }

  // W multiplies the sky term only: nothing to do without one.
  const bool obscure =
      s.obscurance.enabled && (s.lighting == ReliefLighting::SkyOnly || s.skyWeight > 0);
  std::vector<float> transfer;
  ObscuranceField obscuranceField;
  if (obscure) {
    if (!isSupportedObscuranceSampleCount(s.obscurance.samples) || s.obscurance.radiusM <= 0 ||
        (s.obscurance.steps != 1 && s.obscurance.steps != 2)) {
      throw std::invalid_argument("shadeRelief: bad obscurance settings");
    }
    transfer.assign(pixels, 1.0f);
    obscuranceField.heightAt = [&field](glm::vec2 t) { return bilinearHeight(field, t); };
    const glm::vec3 albedo(s.obscuranceAlbedo);
    obscuranceField.albedoAt = [albedo](glm::vec2) { return albedo; };
    obscuranceField.cellSizeM = glm::vec2(glm::dvec2(field.cellSizeXM, field.cellSizeYM));
  }

  auto isWater = [&](int tc, int tr, double height) {
    if (s.waterLevelM && height <= *s.waterLevelM) return true;
    return !s.waterMask.empty() &&
           s.waterMask[static_cast<size_t>(tr) * field.width + static_cast<size_t>(tc)] != 0;
  };

  // Rows in parallel, a band at a time so that progress and interrupts are
  // heard; W first, as it is filtered across pixels before the shading.
  const int bandRows = std::max(1, (1 << 20) / image.width);
  const int passes = obscure ? 2 : 1;
  auto forRows = [&](int pass, const std::function<void(int)>& row) {
    for (int first = 0; first < image.height; first += bandRows) {
      const int end = std::min(image.height, first + bandRows);
      tbb::parallel_for(tbb::blocked_range<int>(first, end), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) row(y);
      });
      throwIfInterrupted();
      if (progress) progress((pass + double(end) / image.height) / passes);
    }
  };

  auto texelOf = [&](int x, int y, double& col, double& row, int& tc, int& tr) {
    col = (x + 0.5) * scaleX - 0.5;
    row = (y + 0.5) * scaleY - 0.5;
    col = std::clamp(col, 0.0, field.width - 1.0);
    row = std::clamp(row, 0.0, field.height - 1.0);
    tc = std::clamp(static_cast<int>(std::lround(col)), 0, field.width - 1);
    tr = std::clamp(static_cast<int>(std::lround(row)), 0, field.height - 1);
  };

  if (obscure) {
    std::vector<uint8_t> voids(pixels, 0);
    forRows(0, [&](int y) {
      for (int x = 0; x < image.width; ++x) {
        double col, row;
        int tc, tr;
        texelOf(x, y, col, row, tc, tr);
        const int cell = interleavePatternIndex(x, y);
        const ObscuranceEstimate e = estimateObscurance(
            obscuranceField, obscuranceCellSampleOffsets(s.obscurance.samples, cell),
            glm::vec2(static_cast<float>(col), static_cast<float>(row)), s.obscurance.radiusM,
            s.obscurance.steps, interleaveRotationRad(cell));
        const size_t i = static_cast<size_t>(y) * image.width + x;
        transfer[i] = e.transfer.r;
        voids[i] = field.isVoid(tc, tr) ? 1 : 0;
      }
    });
    boxFilter4(transfer, voids, image.width, image.height);
  }

  // One shaded point per output pixel, at its centre, or when the output is
  // coarser than the DEM, n x n points on the texels it covers, averaged
  // (a mean, not a sample: no aliasing of ridges finer than a pixel).
  const int subX = std::max(1, static_cast<int>(std::ceil(scaleX - 1e-9)));
  const int subY = std::max(1, static_cast<int>(std::ceil(scaleY - 1e-9)));
  // The value at one point (texel position col, row) of pixel i.
  auto shadePoint = [&](size_t i, double col, double row, int tc, int tr, double height) {
    ShadingInputs in = base;
    const bool water = anyWater && isWater(tc, tr, height);
    in.normal = water ? glm::vec3(0, 0, 1) : surfaceNormal(field, col, row);
    sampleAperture(texels, field.width, field.height, col, row, in.bentNormal, in.apertureRad);
    in.transfer = glm::vec3(obscure ? transfer[i] : 1.0f);
    if (suns.empty()) {
      in.sunDirection = -in.bentNormal;
      return shade(in, s.mode).r;
    }
    if (suns.size() == 1) {
      in.sunDirection = suns[0];
      return shade(in, s.mode).r;
    }
    const std::array<double, 4> w = multidirectionalWeights(aspectDeg(in.normal));
    double sum = 0;
    for (size_t k = 0; k < suns.size(); ++k) {
      in.sunDirection = suns[k];
      sum += w[k] * shade(in, s.mode).r;
    }
    return static_cast<float>(sum / 2);
  };
  forRows(passes - 1, [&](int y) {
    for (int x = 0; x < image.width; ++x) {
      const size_t i = static_cast<size_t>(y) * image.width + x;
      double col, row;
      int tc, tr;
      texelOf(x, y, col, row, tc, tr);
      const double height = field.bilinearHeight(col, row);
      if (s.keepHeights) image.heightM[i] = static_cast<float>(height);
      if (field.isVoid(tc, tr)) {
        image.value[i] = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      if (anyWater && isWater(tc, tr, height)) image.water[i] = 1;
      float v = 0;
      if (subX == 1 && subY == 1) {
        v = shadePoint(i, col, row, tc, tr, height);
      } else {
        double sum = 0;
        int n = 0;
        for (int sy = 0; sy < subY; ++sy) {
          const double r =
              std::clamp((y + (sy + 0.5) / subY) * scaleY - 0.5, 0.0, field.height - 1.0);
          const int pr = std::clamp(static_cast<int>(std::lround(r)), 0, field.height - 1);
          for (int sx = 0; sx < subX; ++sx) {
            const double c =
                std::clamp((x + (sx + 0.5) / subX) * scaleX - 0.5, 0.0, field.width - 1.0);
            const int pc = std::clamp(static_cast<int>(std::lround(c)), 0, field.width - 1);
            if (field.isVoid(pc, pr)) continue;
            sum += shadePoint(i, c, r, pc, pr, field.bilinearHeight(c, r));
            ++n;
          }
        }
        v = static_cast<float>(sum / std::max(n, 1));
      }
      image.value[i] = std::clamp(v, 0.0f, 1.0f);
    }
  });
  return image;
}

}  // namespace

ReliefImage shadeRelief(const Heightfield& field, const ApertureMap& map, const ReliefSettings& s,
                        const std::function<void(double)>& progress) {
  if (field.width < 2 || field.height < 2 || map.width != field.width ||
      map.height != field.height || map.texels.size() != 4 * map.texelCount() ||
      field.z.size() != field.texelCount()) {
    throw std::invalid_argument(
        "shadeRelief: the DEM (at least 2 x 2, whole) and its aperture "
        "map must have the same size");
  }
  return shadeWith(field, FloatTexels{map}, s, progress);
}

ReliefImage shadeRelief(const Heightfield& field, const HalfApertureMap& map,
                        const ReliefSettings& s, const std::function<void(double)>& progress) {
  if (field.width < 2 || field.height < 2 || map.width != field.width ||
      map.height != field.height ||
      map.texels.size() != 4 * static_cast<size_t>(map.width) * map.height ||
      field.z.size() != field.texelCount()) {
    throw std::invalid_argument(
        "shadeRelief: the DEM (at least 2 x 2, whole) and its aperture "
        "map must have the same size");
  }
  return shadeWith(field, HalfTexels{map}, s, progress);
}

HalfApertureMap readHalfApertureMap(ApertureMapReader& reader) {
  HalfApertureMap map;
  map.width = reader.header().width;
  map.height = reader.header().height;
  map.texels.resize(4 * static_cast<size_t>(map.width) * map.height);
  const int band = std::max(1, (1 << 22) / std::max(map.width, 1));
  for (int row = 0; row < map.height; row += band) {
    const int end = std::min(map.height, row + band);
    reader.readHalfRows(row, end, &map.texels[4 * static_cast<size_t>(row) * map.width]);
    throwIfInterrupted();
  }
  return map;
}

HalfApertureMap toHalfApertureMap(const ApertureMap& map) {
  HalfApertureMap out;
  out.width = map.width;
  out.height = map.height;
  out.texels.resize(map.texels.size());
  for (size_t i = 0; i < map.texels.size(); ++i) out.texels[i] = Imath::half(map.texels[i]).bits();
  return out;
}

}  // namespace aal
