#include "aperture/terrain/light/obscurance.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

#include <glm/geometric.hpp>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/light/obscurance_samples.h"

namespace aal {

namespace {
constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
}

float defaultObscuranceRadiusM(glm::dvec2 cellSizeM, glm::dvec2 demExtentM) {
  const double cells = kDefaultObscuranceRadiusCells * std::max(cellSizeM.x, cellSizeM.y);
  return static_cast<float>(std::min(cells, std::min(demExtentM.x, demExtentM.y)));
}

void checkObscuranceSettings(const ObscuranceSettings& s, glm::dvec2 demExtentM) {
  if (!isSupportedObscuranceSampleCount(s.samples)) {
    throw InputError("--obscurance-samples must be 8, 16 or 32, got " + std::to_string(s.samples));
  }
  if (s.steps != 1 && s.steps != 2) {
    throw InputError("--obscurance-steps must be 1 or 2, got " + std::to_string(s.steps));
  }
  // Compared in the radius's own precision: the default, the shorter side
  // itself on a narrow DEM, is that side rounded to a float, which may lie a
  // hair above the double (a 64 x 5 DEM of 0.3 m cells was refused for the
  // radius it had not been given, "at most 1.200000 m, got 1.200000").
  const float limit = static_cast<float>(std::min(demExtentM.x, demExtentM.y));
  if (!(s.radiusM > 0) || !std::isfinite(s.radiusM) || s.radiusM > limit) {
    std::ostringstream message;
    message << "--obscurance-radius " << s.radiusM
            << " m: the radius must be more than 0 and at most the DEM's shorter side, " << limit
            << " m; give one in that range, or leave the option out for the default ("
            << kDefaultObscuranceRadiusCells << " cells, at most that side)";
    throw InputError(message.str());
  }
}

float bilinearHeight(const Heightfield& field, glm::vec2 texel) {
  // NaN passes std::clamp and would become an index: take texel 0.
  const float x =
      std::clamp(std::isnan(texel.x) ? 0.0f : texel.x, 0.0f, static_cast<float>(field.width - 1));
  const float y =
      std::clamp(std::isnan(texel.y) ? 0.0f : texel.y, 0.0f, static_cast<float>(field.height - 1));
  const int x0 = std::min(static_cast<int>(x), field.width - 1);
  const int y0 = std::min(static_cast<int>(y), field.height - 1);
  const int x1 = std::min(x0 + 1, field.width - 1), y1 = std::min(y0 + 1, field.height - 1);
  const float fx = x - static_cast<float>(x0), fy = y - static_cast<float>(y0);
  const float top = field.at(x0, y0) * (1 - fx) + field.at(x1, y0) * fx;
  const float bottom = field.at(x0, y1) * (1 - fx) + field.at(x1, y1) * fx;
  return top * (1 - fy) + bottom * fy;
}

glm::vec3 obscuranceNormal(const ObscuranceField& field, glm::vec2 texel) {
  const float dx =
      field.heightAt(texel + glm::vec2(1, 0)) - field.heightAt(texel - glm::vec2(1, 0));
  // North is row - 1.
  const float dy =
      field.heightAt(texel - glm::vec2(0, 1)) - field.heightAt(texel + glm::vec2(0, 1));
  return glm::normalize(
      glm::vec3(-dx / (2.0f * field.cellSizeM.x), -dy / (2.0f * field.cellSizeM.y), 1.0f));
}

void obscuranceTangentFrame(glm::vec3 normal, float rotationRad, glm::vec3& tangent,
                            glm::vec3& bitangent) {
  // A heightfield normal has n.z > 0, so it is never parallel to y.
  const glm::vec3 t = glm::normalize(glm::cross(glm::vec3(0, 1, 0), normal));
  const glm::vec3 b = glm::cross(normal, t);
  const float c = std::cos(rotationRad), s = std::sin(rotationRad);
  tangent = c * t + s * b;
  bitangent = c * b - s * t;
}

int interleavePatternIndex(int x, int y) {
  // Bayer's ordered-dither matrix: neighbouring pixels get distant indices.
  static constexpr int kBayer[4][4] = {
      {0, 8, 2, 10}, {12, 4, 14, 6}, {3, 11, 1, 9}, {15, 7, 13, 5}};
  return kBayer[y & 3][x & 3];
}

float interleaveRotationRad(int index) {
  return kTwoPi * static_cast<float>(index) / 16.0f;
}

ObscuranceEstimate estimateObscurance(const ObscuranceField& field,
                                      const std::vector<glm::vec3>& offsets, glm::vec2 texel,
                                      float radiusM, int steps, float rotationRad) {
  const float z = field.heightAt(texel);
  const glm::vec3 n = obscuranceNormal(field, texel);
  glm::vec3 t, b;
  obscuranceTangentFrame(n, rotationRad, t, b);
  float open = 0;               // Σ S_i
  glm::vec3 occludedAlbedo{0};  // Σ (1 - S_i) a(p_i)
  for (const glm::vec3& o : offsets) {
    const glm::vec3 ray = radiusM * (o.x * t + o.y * b + o.z * n);
    bool outer = true;
    for (int j = 1; j <= steps && outer; ++j) {
      // Offsets from x in metres, so large world coordinates lose no precision.
      const glm::vec3 d = ray * (static_cast<float>(j) / static_cast<float>(steps));
      const glm::vec2 q = texel + glm::vec2(d.x / field.cellSizeM.x, -d.y / field.cellSizeM.y);
      if (z + d.z < field.heightAt(q)) {
        outer = false;
        occludedAlbedo += glm::clamp(field.albedoAt(q), glm::vec3(0), glm::vec3(1));
      }
    }
    if (outer) open += 1;
  }
  const float count = static_cast<float>(offsets.size());
  ObscuranceEstimate e;
  e.obscurance = open / count;
  // n - Σ(1-S)a >= Σ S since a <= 1, so W <= 1; W >= O since the sum is >= 0.
  for (int c = 0; c < 3; ++c) e.transfer[c] = open > 0 ? open / (count - occludedAlbedo[c]) : 0.0f;
  return e;
}

}  // namespace aal
