#include "aperture/engine/supersampling.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <glm/common.hpp>
#include <glm/vec4.hpp>

#include "aperture/terrain/light/tone_map.h"

namespace aal {

FrameResult downsampleFrame(const FrameResult& big, uint32_t factor, float exposure, bool raw,
                            bool keepLinear) {
  if (factor == 0 || big.width % factor != 0 || big.height % factor != 0) {
    throw std::invalid_argument("downsampleFrame: the frame's size is not a multiple of " +
                                std::to_string(factor));
  }
  if (big.linear.size() != size_t(big.width) * big.height * 4) {
    throw std::invalid_argument("downsampleFrame: the frame has no linear values");
  }
  FrameResult out;
  out.width = big.width / factor;
  out.height = big.height / factor;
  out.passMilliseconds = big.passMilliseconds;
  out.triangles = big.triangles;
  out.patchesPerLevel = big.patchesPerLevel;
  const size_t pixels = size_t(out.width) * out.height;
  out.display.resize(pixels * 4);
  if (keepLinear) out.linear.resize(pixels * 4);
  const float weight = 1.0f / float(factor * factor);
  const auto to8 = [](float v) {
    return static_cast<uint8_t>(std::lround(255.0f * std::clamp(v, 0.0f, 1.0f)));
  };
  for (uint32_t y = 0; y < out.height; ++y) {
    for (uint32_t x = 0; x < out.width; ++x) {
      // Colour over the covered points (alpha-weighted: unassociated, as the
      // renderer's frames and the PNG are), over all where none is covered.
      glm::vec3 sum(0.0f), covered(0.0f);
      float alpha = 0.0f;
      for (uint32_t j = 0; j < factor; ++j) {
        const float* row = &big.linear[4 * ((size_t(y) * factor + j) * big.width + x * factor)];
        for (uint32_t i = 0; i < factor; ++i) {
          const glm::vec3 rgb(row[4 * i], row[4 * i + 1], row[4 * i + 2]);
          sum += rgb;
          covered += row[4 * i + 3] * rgb;
          alpha += row[4 * i + 3];
        }
      }
      const glm::vec4 mean(alpha > 0.0f ? covered / alpha : sum * weight, alpha * weight);
      const size_t o = 4 * (size_t(y) * out.width + x);
      const glm::vec3 shown =
          raw ? glm::clamp(glm::vec3(mean), 0.0f, 1.0f) : toneMap(glm::vec3(mean), exposure);
      for (int k = 0; k < 3; ++k) out.display[o + k] = to8(shown[k]);
      out.display[o + 3] = to8(mean.a);
      if (keepLinear) {
        for (int k = 0; k < 4; ++k) out.linear[o + k] = mean[k];
      }
    }
  }
  return out;
}

namespace {

// The settings of a renderer of `factor` times the output's width and
// height: an explicit LOD error stays in output pixels.
FrameSettings pointSettings(FrameSettings settings, uint32_t factor) {
  settings.lod.maxErrorPixels *= static_cast<double>(factor);
  return settings;
}

}  // namespace

FrameResult renderSupersampled(TerrainRenderer& renderer, const TerrainScene& scene,
                               FrameSettings settings, uint32_t factor, bool keepLinear,
                               bool accumulate) {
  const auto render = [&](bool linear) {
    return accumulate ? renderer.renderAccumulated(scene, settings, linear)
                      : renderer.render(scene, settings, linear);
  };
  if (factor <= 1) return render(keepLinear);
  settings = pointSettings(settings, factor);
  return downsampleFrame(render(true), factor, settings.lighting.exposure,
                         isDebugMode(settings.mode), keepLinear);
}

void startAccumulation(TerrainRenderer& renderer, const TerrainScene& scene,
                       const FrameSettings& settings, uint32_t factor) {
  renderer.restartTemporal();
  const FrameSettings points = pointSettings(settings, std::max(factor, 1u));
  for (int i = 0; i < kAccumulationLeadFrames; ++i) renderer.accumulate(scene, points);
}

}  // namespace aal
