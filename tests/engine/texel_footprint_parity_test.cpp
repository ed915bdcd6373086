// The GLSL footprint probes (shaders/texel_footprint.glsl) agree with their
// C++ twin (terrain/view/texel_footprint.h) when run on the device.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/vec4.hpp>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/view/texel_footprint.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

class TexelFootprintParity : public VulkanTest {};

TEST_F(TexelFootprintParity, GlslProbesMatchCpp) {
  // Footprints from 1/100 to 1000 texels, every anisotropy up to 64:1 and
  // beyond (no width at all), sheared, in any orientation, and the special
  // ones: square, axis-aligned ratios at the probe counts' thresholds, zero.
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<glm::vec4> queries = {{0, 0, 0, 0},    {4, 0, 0, 4},   {1, 0, 0, 4},
                                    {1, 0, 0, 2.5f}, {0, 8, -2, 0},  {2, 0, 2, 0.5f},
                                    {0, 0, 0, 8},    {1, 0, 0, 200}, {300, 0, 0, 900}};
  while (queries.size() < 20000) {
    const float length = std::pow(10.0f, -2.0f + 5.0f * unit(rng));
    const float angle = 6.2831853f * unit(rng), across = std::exp2(-7.0f * unit(rng));
    const glm::vec2 along(std::cos(angle), std::sin(angle)), normal(-along.y, along.x);
    const glm::vec2 dx = length * along;
    const glm::vec2 dy = length * ((2.0f * unit(rng) - 1.0f) * along + across * normal);
    queries.push_back(unit(rng) < 0.5f ? glm::vec4(dx, dy) : glm::vec4(dy, dx));
  }
  const uint32_t count = static_cast<uint32_t>(queries.size());
  Buffer input(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               MemoryIntent::Upload);
  input.write(queries.data(), count * sizeof(glm::vec4));
  Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryIntent::Readback);
  const ComputePipeline pipeline(device(), "texel_footprint_parity.comp", 2 * sizeof(uint32_t));
  const uint32_t groups =
      (count + AAL_FOOTPRINT_PARITY_GROUP_SIZE - 1) / AAL_FOOTPRINT_PARITY_GROUP_SIZE;
  // Every limit a frame may ask for (FrameSettings::anisotropy); the last
  // run, the default, stays in `answers` for the special footprints below.
  std::vector<glm::vec4> answers(count);
  for (int32_t most = 1; most <= kMaxFootprintProbes; ++most) {
    const struct {
      uint32_t count;
      int32_t maxProbes;
    } push{count, most};
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      pipeline.record(cmd, {&input, &output}, &push, groups);
    });
    output.read(answers.data(), count * sizeof(glm::vec4));

    // Both evaluate the same single-precision expressions; the device's
    // log2, exp2 and division need not be correctly rounded, so the level and
    // the step may differ by a few ulps, and the count only where the axes'
    // ratio sits on a threshold (within that rounding of an integer).
    int countsApart = 0;
    double worstLod = 0, worstStep = 0;
    for (uint32_t i = 0; i < count; ++i) {
      const glm::vec2 dx(queries[i].x, queries[i].y), dy(queries[i].z, queries[i].w);
      const FootprintProbes cpu = footprintProbes(dx, dy, most);
      const glm::vec4 gpu = answers[i];
      if (int(gpu.x) != cpu.count) {
        ++countsApart;
        continue;
      }
      worstLod = std::max(worstLod, std::abs(double(gpu.y) - cpu.lod));
      const double length = std::max(1e-30, double(std::hypot(cpu.step.x, cpu.step.y)));
      worstStep = std::max(
          worstStep, std::hypot(double(gpu.z) - cpu.step.x, double(gpu.w) - cpu.step.y) / length);
    }
    std::printf(
        "at most %d probes, %u footprints: %d probe counts apart, worst |dlod| %.3g, worst step "
        "%.3g relative\n",
        most, count, countsApart, worstLod, worstStep);
    EXPECT_LE(countsApart, 2) << most;
    EXPECT_LT(worstLod, 1e-5) << most;
    EXPECT_LT(worstStep, 1e-5) << most;
  }
  // The special footprints exactly.
  EXPECT_EQ(answers[0], glm::vec4(1, 0, 0, 0));
  EXPECT_EQ(answers[1].x, 1.0f);
  EXPECT_EQ(answers[1].y, 2.0f);
  EXPECT_EQ(answers[2], glm::vec4(4, 0, 0, 1));
  EXPECT_EQ(answers[3].x, 3.0f);
}

}  // namespace
}  // namespace aal
