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

// Throws std::invalid_argument for settings the relief cannot be shaded
// with on this DEM.
void checkReliefSettings(const Heightfield& field, const ReliefSettings& s, bool obscure) {
  if (!(s.skyWeight >= 0 && s.skyWeight <= 1) ||
      (s.mode != ShadingMode::Approx && s.mode != ShadingMode::Exact)) {
    throw std::invalid_argument("shadeRelief: sky weight in [0, 1], mode approx or exact");
  }
  if (!s.waterMask.empty() && s.waterMask.size() != field.texelCount()) {
    throw std::invalid_argument("shadeRelief: the water mask must have the DEM's size");
  }
  if (obscure &&
      (!isSupportedObscuranceSampleCount(s.obscurance.samples) || s.obscurance.radiusM <= 0 ||
       (s.obscurance.steps != 1 && s.obscurance.steps != 2))) {
    throw std::invalid_argument("shadeRelief: bad obscurance settings");
  }
}

// W multiplies the sky term only: nothing to do without one.
bool obscures(const ReliefSettings& s) {
  return s.obscurance.enabled && (s.lighting == ReliefLighting::SkyOnly || s.skyWeight > 0);
}

bool asksForWater(const ReliefSettings& s) {
  return s.waterLevelM.has_value() || !s.waterMask.empty();
}

// The output raster, zeroed: values, and heights and water flags when asked for.
ReliefImage blankReliefImage(const Heightfield& field, const ReliefSettings& s) {
  ReliefImage image;
  image.width = s.outWidth > 0 ? s.outWidth : field.width;
  image.height = s.outHeight > 0 ? s.outHeight : field.height;
  const size_t pixels = static_cast<size_t>(image.width) * image.height;
  image.value.assign(pixels, 0.0f);
  if (s.keepHeights) image.heightM.assign(pixels, 0.0f);
  if (asksForWater(s)) image.water.assign(pixels, 0);
  return image;
}

// The suns' directions: none for the sky alone; the weights of
// Multidirectional depend on the aspect and are set per point.
std::vector<glm::vec3> reliefSuns(const ReliefSettings& s) {
  std::vector<glm::vec3> suns;
  if (s.lighting == ReliefLighting::Multidirectional) {
    for (const double a : kMultidirectionalAzimuthsDeg) {
      suns.push_back(sunDirection(a, s.sunElevationDeg));
    }
  } else if (s.lighting == ReliefLighting::Sun) {
    suns.push_back(sunDirection(s.sunAzimuthDeg, s.sunElevationDeg));
  }
  return suns;
}

// The shading inputs every point shares: the irradiances normalised as
// relief.h says, albedo pi.
ShadingInputs reliefBaseInputs(const ReliefSettings& s) {
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
  return base;
}

// A point on the DEM: continuous texel position and the nearest texel.
struct TexelPoint {
  double col, row;
  int tc, tr;
};

// The output pixels laid over the DEM's texels (ReliefSettings::outWidth).
struct PixelGrid {
  PixelGrid(const Heightfield& f, int imageWidth, int imageHeight)
      : field(f),
        width(imageWidth),
        height(imageHeight),
        scaleX(double(f.width) / imageWidth),
        scaleY(double(f.height) / imageHeight),
        subX(std::max(1, static_cast<int>(std::ceil(scaleX - 1e-9)))),
        subY(std::max(1, static_cast<int>(std::ceil(scaleY - 1e-9)))) {}

  // The point at pixel coordinates (x, y) in output pixels, 0.5 = the
  // centre of the first, clamped to the DEM.
  TexelPoint at(double x, double y) const {
    const double col = std::clamp(x * scaleX - 0.5, 0.0, field.width - 1.0);
    const double row = std::clamp(y * scaleY - 0.5, 0.0, field.height - 1.0);
    return {col, row, std::clamp(static_cast<int>(std::lround(col)), 0, field.width - 1),
            std::clamp(static_cast<int>(std::lround(row)), 0, field.height - 1)};
  }
  TexelPoint centre(int x, int y) const { return at(x + 0.5, y + 0.5); }

  const Heightfield& field;
  int width, height;      // output pixels
  double scaleX, scaleY;  // texels per pixel
  // Points per pixel along x and y: one, or when the output is coarser than
  // the DEM, n x n points on the texels it covers, averaged (a mean, not a
  // sample: no aliasing of ridges finer than a pixel).
  int subX, subY;
};

// Runs a pass over the output rows in parallel, a band at a time so that
// progress and interrupts are heard.
class RowBands {
 public:
  RowBands(const PixelGrid& grid, int passes, const std::function<void(double)>& progress)
      : height_(grid.height),
        bandRows_(std::max(1, (1 << 20) / grid.width)),
        passes_(passes),
        progress_(progress) {}

  template <class Row>
  void run(int pass, const Row& row) const {
    for (int first = 0; first < height_; first += bandRows_) {
      const int end = std::min(height_, first + bandRows_);
      tbb::parallel_for(tbb::blocked_range<int>(first, end), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) row(y);
      });
      throwIfInterrupted();
      if (progress_) progress_((pass + double(end) / height_) / passes_);
    }
  }
  int lastPass() const { return passes_ - 1; }

 private:
  int height_, bandRows_, passes_;
  const std::function<void(double)>& progress_;
};

// The ambient transfer W of every output pixel, at its centre, filtered
// across pixels (boxFilter4): the first pass, before the shading.
std::vector<float> obscuranceTransfer(const Heightfield& field, const ReliefSettings& s,
                                      const PixelGrid& grid, const RowBands& bands) {
  ObscuranceField obscuranceField;
  obscuranceField.heightAt = [&field](glm::vec2 t) { return bilinearHeight(field, t); };
  const glm::vec3 albedo(s.obscuranceAlbedo);
  obscuranceField.albedoAt = [albedo](glm::vec2) { return albedo; };
  obscuranceField.cellSizeM = glm::vec2(glm::dvec2(field.cellSizeXM, field.cellSizeYM));
  const size_t pixels = static_cast<size_t>(grid.width) * grid.height;
  std::vector<float> transfer(pixels, 1.0f);
  std::vector<uint8_t> voids(pixels, 0);
  bands.run(0, [&](int y) {
    for (int x = 0; x < grid.width; ++x) {
      const TexelPoint p = grid.centre(x, y);
      const int cell = interleavePatternIndex(x, y);
      const ObscuranceEstimate e = estimateObscurance(
          obscuranceField, obscuranceCellSampleOffsets(s.obscurance.samples, cell),
          glm::vec2(static_cast<float>(p.col), static_cast<float>(p.row)), s.obscurance.radiusM,
          s.obscurance.steps, interleaveRotationRad(cell));
      const size_t i = static_cast<size_t>(y) * grid.width + x;
      transfer[i] = e.transfer.r;
      voids[i] = field.isVoid(p.tc, p.tr) ? 1 : 0;
    }
  });
  boxFilter4(transfer, voids, grid.width, grid.height);
  return transfer;
}

// Shades the output pixels: the last pass.
template <class Texels>
class ReliefShader {
 public:
  // `transfer`: W per output pixel, or empty for none.
  ReliefShader(const Heightfield& field, const Texels& texels, const ReliefSettings& s,
               const PixelGrid& grid, const std::vector<float>& transfer)
      : field_(field),
        texels_(texels),
        s_(s),
        grid_(grid),
        transfer_(transfer),
        suns_(reliefSuns(s)),
        base_(reliefBaseInputs(s)),
        anyWater_(asksForWater(s)) {}

  // Row y of the image: value, and the height and water flags when asked for.
  void shadeRow(int y, ReliefImage& image) const {
    for (int x = 0; x < grid_.width; ++x) {
      const size_t i = static_cast<size_t>(y) * grid_.width + x;
      const TexelPoint p = grid_.centre(x, y);
      const double height = field_.bilinearHeight(p.col, p.row);
      if (s_.keepHeights) image.heightM[i] = static_cast<float>(height);
      if (field_.isVoid(p.tc, p.tr)) {
        image.value[i] = std::numeric_limits<float>::quiet_NaN();
        continue;
      }
      if (anyWater_ && isWater(p, height)) image.water[i] = 1;
      const float v =
          grid_.subX == 1 && grid_.subY == 1 ? shadePoint(i, p, height) : meanOverPixel(i, x, y);
      image.value[i] = std::clamp(v, 0.0f, 1.0f);
    }
  }

 private:
  bool isWater(const TexelPoint& p, double height) const {
    if (s_.waterLevelM && height <= *s_.waterLevelM) return true;
    return !s_.waterMask.empty() &&
           s_.waterMask[static_cast<size_t>(p.tr) * field_.width + static_cast<size_t>(p.tc)] != 0;
  }

  // The mean of the values at subX x subY points spread over pixel (x, y),
  // voids left out.
  float meanOverPixel(size_t i, int x, int y) const {
    double sum = 0;
    int n = 0;
    for (int sy = 0; sy < grid_.subY; ++sy) {
      for (int sx = 0; sx < grid_.subX; ++sx) {
        const TexelPoint p = grid_.at(x + (sx + 0.5) / grid_.subX, y + (sy + 0.5) / grid_.subY);
        if (field_.isVoid(p.tc, p.tr)) continue;
        sum += shadePoint(i, p, field_.bilinearHeight(p.col, p.row));
        ++n;
      }
    }
    return static_cast<float>(sum / std::max(n, 1));
  }

  // The value at one point of pixel i (whose W it takes).
  float shadePoint(size_t i, const TexelPoint& p, double height) const {
    ShadingInputs in = base_;
    const bool water = anyWater_ && isWater(p, height);
    in.normal = water ? glm::vec3(0, 0, 1) : surfaceNormal(field_, p.col, p.row);
    sampleAperture(texels_, field_.width, field_.height, p.col, p.row, in.bentNormal,
                   in.apertureRad);
    in.transfer = glm::vec3(transfer_.empty() ? 1.0f : transfer_[i]);
    if (suns_.empty()) {
      in.sunDirection = -in.bentNormal;
      return shade(in, s_.mode).r;
    }
    if (suns_.size() == 1) {
      in.sunDirection = suns_[0];
      return shade(in, s_.mode).r;
    }
    const std::array<double, 4> w = multidirectionalWeights(aspectDeg(in.normal));
    double sum = 0;
    for (size_t k = 0; k < suns_.size(); ++k) {
      in.sunDirection = suns_[k];
      sum += w[k] * shade(in, s_.mode).r;
    }
    return static_cast<float>(sum / 2);
  }

  const Heightfield& field_;
  const Texels& texels_;
  const ReliefSettings& s_;
  const PixelGrid& grid_;
  const std::vector<float>& transfer_;
  std::vector<glm::vec3> suns_;
  ShadingInputs base_;
  bool anyWater_;
};

template <class Texels>
ReliefImage shadeWith(const Heightfield& field, const Texels& texels, const ReliefSettings& s,
                      const std::function<void(double)>& progress) {
  const bool obscure = obscures(s);
  checkReliefSettings(field, s, obscure);
  ReliefImage image = blankReliefImage(field, s);
  const PixelGrid grid(field, image.width, image.height);
  const RowBands bands(grid, obscure ? 2 : 1, progress);
  const std::vector<float> transfer =
      obscure ? obscuranceTransfer(field, s, grid, bands) : std::vector<float>();
  const ReliefShader<Texels> shader(field, texels, s, grid, transfer);
  bands.run(bands.lastPass(), [&](int y) { shader.shadeRow(y, image); });
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
