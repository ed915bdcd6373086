// The GLSL sky and tone map (shaders/sky.glsl, shaders/tone_map.glsl) agree
// with the C++ ones (terrain/light/sky_model.h, terrain/light/tone_map.h) when run on the
// device, with PreethamSky passed in the renderer's std140 layout.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/sky_model.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

struct SkyQuery {       // mirrors sky_parity.comp
  glm::vec4 direction;  // xyz, w: sky index
};
static_assert(sizeof(SkyQuery) == 16, "std430 layout");

// Runs `shader` over `count` queries with the given storage buffers (the last
// is the output) and the query count as push constant.
void dispatch(const Device& device, const char* shader, const std::vector<const Buffer*>& buffers,
              uint32_t count) {
  const ComputePipeline pipeline(device, shader, sizeof(uint32_t));
  const uint32_t groups = (count + AAL_SKY_PARITY_GROUP_SIZE - 1) / AAL_SKY_PARITY_GROUP_SIZE;
  submitAndWait(device,
                [&](VkCommandBuffer cmd) { pipeline.record(cmd, buffers, &count, groups); });
}

template <typename T>
Buffer upload(const Device& device, const std::vector<T>& data) {
  Buffer buffer(device, data.size() * sizeof(T), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryIntent::Upload);
  buffer.write(data.data(), data.size() * sizeof(T));
  return buffer;
}

glm::vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<float> n;
  return glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
}

class SkyParity : public VulkanTest {};

TEST_F(SkyParity, GlslSkyRadianceMatchesCpp) {
  // Skies from noon to night, clear to hazy, at assorted azimuths.
  std::vector<PreethamSky> skies;
  // (76.85°: jacksboro's summer noon, whose horizon band the daylight locus
  // lift of sky.glsl changes; 45° and 37.5°: the midday CCT floor at full and
  // half strength; 60° and above: at full.)
  for (double elevation :
       {90.0, 76.85, 60.0, 45.0, 37.5, 30.0, 10.0, 2.0, 0.0, -2.0, -5.0, -10.0}) {
    for (double turbidity : {2.0, 2.5, 4.0, 9.0}) {
      const double azimuth = 37.0 * double(skies.size());
      skies.push_back(makePreethamSky(sunDirection(azimuth, elevation), turbidity));
    }
  }
  // Random directions (a quarter below the horizon), directions within a few
  // degrees of the sun, and grazing ones.
  std::vector<SkyQuery> queries;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (size_t s = 0; s < skies.size(); ++s) {
    const glm::vec3 sun(skies[s].sunDirection);
    const float index = static_cast<float>(s);
    for (int i = 0; i < 100; ++i) {
      glm::vec3 d = randomUnit(rng);
      if (i % 4 != 0) d.z = std::abs(d.z);
      queries.push_back({glm::vec4(d, index)});
    }
    for (int i = 0; i < 40; ++i) {
      const glm::vec3 offset = 0.1f * unit(rng) * unit(rng) * randomUnit(rng);
      queries.push_back({glm::vec4(glm::normalize(sun + offset), index)});
    }
    queries.push_back({glm::vec4(sun, index)});
    for (int i = 0; i < 20; ++i) {
      const float az = 6.2831853f * unit(rng);
      queries.push_back(
          {glm::vec4(std::cos(az), std::sin(az), 0.002f * (unit(rng) - 0.5f), index)});
    }
    queries.push_back({glm::vec4(0, 0, 1, index)});
    queries.push_back({glm::vec4(0, 0, -1, index)});
    // The band 1-10° above the horizon all around, where a high sun's
    // chromaticity y falls below the daylight locus and is lifted, and where
    // the midday floor moves x (daylightChromaticity in sky.glsl and
    // terrain/light/sky_model.h).
    for (double e : {1.0, 3.0, 6.0, 10.0}) {
      for (double az = 0.0; az < 360.0; az += 30.0) {
        queries.push_back({glm::vec4(sunDirection(az, e), index)});
      }
    }
  }
  const uint32_t count = static_cast<uint32_t>(queries.size());

  Buffer skyBuffer = upload(device(), skies);
  Buffer queryBuffer = upload(device(), queries);
  Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryIntent::Readback);
  dispatch(device(), "sky_parity.comp", {&skyBuffer, &queryBuffer, &output}, count);
  std::vector<glm::vec4> answers(count);
  output.read(answers.data(), count * sizeof(glm::vec4));

  // Both sides evaluate the same single-precision expression; they differ
  // only in how exp, atan, sqrt and division round: lavapipe's exp and atan
  // are polynomial approximations good to ~1e-6 relative, not correctly
  // rounded. Each of Y, x, y is a product of two factors with an exp, and the
  // xyY -> RGB step sums terms up to ~3x the luminance with both signs, so a
  // channel can be off by ~5 x 2 x 1e-6 of the luminance. (Near the horizon
  // B / cos(theta) reaches ~-1000, but its exp term then vanishes on both
  // sides.) Each channel is compared against the sample's luminance with a
  // bound of 5e-5; measured worst: 9.1e-6.
  double worst = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    const PreethamSky& sky = skies[static_cast<size_t>(queries[i].direction.w)];
    const glm::vec3 cpu = skyRadiance(sky, glm::vec3(queries[i].direction));
    const glm::vec3 gpu(answers[i]);
    const float scale = std::max(luminance(cpu), 1e-6f);
    for (int c = 0; c < 3; ++c) {
      ASSERT_TRUE(std::isfinite(gpu[c])) << i;
      const double error = std::abs(double(gpu[c]) - double(cpu[c])) / scale;
      EXPECT_LT(error, 5e-5) << "query " << i << " channel " << c << " cpu " << cpu[c] << " gpu "
                             << gpu[c];
      worst = std::max(worst, error);
    }
  }
  RecordProperty("worst_relative_error", std::to_string(worst));
  std::printf("sky GLSL vs C++ over %u directions x skies: worst %.3g of the luminance\n", count,
              worst);
}

TEST_F(SkyParity, GlslToneMapMatchesCpp) {
  std::vector<glm::vec4> queries;  // rgb linear HDR, w: exposure
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> logValue(-5.0f, 3.0f), logExposure(-3.0f, 1.0f);
  for (int i = 0; i < 4000; ++i) {
    queries.emplace_back(std::pow(10.0f, logValue(rng)), std::pow(10.0f, logValue(rng)),
                         std::pow(10.0f, logValue(rng)), std::pow(10.0f, logExposure(rng)));
  }
  // Black, negative, beyond the white point, and around the sRGB knee.
  for (float v : {0.0f, -1.0f, 11.2f, 1e6f}) queries.emplace_back(v, v, v, 1.0f);
  for (float y = 0.0025f; y < 0.0037f; y += 0.0001f) {
    const float x = inverseFilmicCurve(y);
    queries.emplace_back(x, x, x, 1.0f);
  }
  const uint32_t count = static_cast<uint32_t>(queries.size());

  Buffer queryBuffer = upload(device(), queries);
  Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryIntent::Readback);
  dispatch(device(), "tone_map_parity.comp", {&queryBuffer, &output}, count);
  std::vector<glm::vec4> answers(count);
  output.read(answers.data(), count * sizeof(glm::vec4));

  // Display values in [0, 1]: the curve is a ratio of quadratics (a few ulp)
  // and pow(c, 1/2.4) is exp2(log2(c) / 2.4) on lavapipe, good to ~1e-6.
  // 2e-5 is 1/200 of an 8-bit step, so the two round to different 8-bit
  // codes only at near-ties; measured worst: 2.4e-7.
  double worst = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 cpu = toneMap(glm::vec3(queries[i]), queries[i].w);
    for (int c = 0; c < 3; ++c) {
      const double error = std::abs(double(answers[i][c]) - double(cpu[c]));
      EXPECT_LT(error, 2e-5) << "query " << i << " channel " << c;
      worst = std::max(worst, error);
    }
  }
  RecordProperty("worst_abs_error", std::to_string(worst));
  std::printf("tone map GLSL vs C++ over %u colours: worst %.3g\n", count, worst);
}

}  // namespace
}  // namespace aal
