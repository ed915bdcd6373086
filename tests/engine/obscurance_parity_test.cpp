// estimateObscurance() of shaders/obscurance.glsl agrees with
// terrain/light/obscurance.h on the device, on a synthetic heightfield, with every
// interleave cell's sample set.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include <glm/vec4.hpp>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/terrain/light/obscurance_samples.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

struct Push {  // mirrors obscurance_parity.comp
  glm::ivec2 size;
  glm::vec2 cellSizeM;
  float radiusM;
  int samples;
  int steps;
  uint32_t count;
};
static_assert(sizeof(Push) == 32, "push constant layout");

class ObscuranceParity : public VulkanTest {};

TEST_F(ObscuranceParity, GlslEstimatorMatchesCppOnATerrain) {
  SyntheticTerrainOptions o;
  o.width = 96;
  o.height = 80;
  o.cellSizeM = 20;
  o.featureSizeTexels = 32;
  o.amplitudeM = 500;
  o.ridged = true;  // sharp creases: many partly occluded points
  const Heightfield h = makeSyntheticTerrain(o);
  // A blocky albedo image, nearest-sampled on both sides.
  std::vector<glm::vec4> albedo(h.texelCount());
  for (int row = 0; row < h.height; ++row) {
    for (int col = 0; col < h.width; ++col) {
      albedo[h.index(col, row)] = {0.1f + 0.8f * ((col / 8) % 2), 0.2f + 0.6f * ((row / 8) % 2),
                                   0.5f, 0};
    }
  }
  const ObscuranceField field{
      [&](glm::vec2 t) { return bilinearHeight(h, t); },
      [&](glm::vec2 t) {
        const int col = std::clamp(static_cast<int>(std::floor(t.x + 0.5f)), 0, h.width - 1);
        const int row = std::clamp(static_cast<int>(std::floor(t.y + 0.5f)), 0, h.height - 1);
        return glm::vec3(albedo[h.index(col, row)]);
      },
      glm::vec2(20.0f)};

  Buffer heights(device(), h.texelCount() * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryIntent::Upload);
  heights.write(h.z.data(), h.texelCount() * sizeof(float));
  Buffer albedoBuffer(device(), albedo.size() * sizeof(glm::vec4),
                      VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryIntent::Upload);
  albedoBuffer.write(albedo.data(), albedo.size() * sizeof(glm::vec4));
  const ComputePipeline pipeline(device(), "obscurance_parity.comp", sizeof(Push));

  std::mt19937 rng(23);
  std::uniform_real_distribution<float> col(0.0f, 95.0f), row(0.0f, 79.0f), unit(0.0f, 1.0f);
  size_t compared = 0, flipped = 0, occluded = 0;
  std::vector<size_t> perSet(kObscuranceSampleSets);
  double worst = 0;
  for (int n : {8, 16, 32}) {
    for (int steps : {1, 2}) {
      // Every interleave cell's set, set k's sample i at k * n + i.
      std::vector<glm::vec4> offsetData;
      for (int k = 0; k < kObscuranceSampleSets; ++k) {
        for (const glm::vec3& v : obscuranceCellSampleOffsets(n, k)) offsetData.emplace_back(v, 0);
      }
      // Each query with one of the 16 sets; half with rotation 0, as the
      // renderer uses them, half with a random rotation of the frame.
      std::vector<glm::vec4> queries(2000);
      for (size_t i = 0; i < queries.size(); ++i) {
        const float rotation = i % 2 ? 0.0f : 6.2831853f * unit(rng);
        const int set = static_cast<int>((i / 2) % kObscuranceSampleSets);
        queries[i] = {col(rng), row(rng), rotation, static_cast<float>(set)};
        ++perSet[static_cast<size_t>(set)];
      }
      const float radiusM = 60.0f + 140.0f * unit(rng);
      const uint32_t count = static_cast<uint32_t>(queries.size());
      Buffer input(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                   MemoryIntent::Upload);
      input.write(queries.data(), count * sizeof(glm::vec4));
      Buffer offsetBuffer(device(), offsetData.size() * sizeof(glm::vec4),
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryIntent::Upload);
      offsetBuffer.write(offsetData.data(), offsetData.size() * sizeof(glm::vec4));
      Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                    MemoryIntent::Readback);
      const Push push{{h.width, h.height}, {20.0f, 20.0f}, radiusM, n, steps, count};
      submitAndWait(device(), [&](VkCommandBuffer cmd) {
        pipeline.record(
            cmd, {&input, &heights, &albedoBuffer, &offsetBuffer, &output}, &push,
            (count + AAL_OBSCURANCE_PARITY_GROUP_SIZE - 1) / AAL_OBSCURANCE_PARITY_GROUP_SIZE);
      });
      std::vector<glm::vec4> answers(count);
      output.read(answers.data(), count * sizeof(glm::vec4));
      for (uint32_t i = 0; i < count; ++i) {
        const ObscuranceEstimate e = estimateObscurance(
            field, obscuranceCellSampleOffsets(n, static_cast<int>(queries[i].w)),
            {queries[i].x, queries[i].y}, radiusM, steps, queries[i].z);
        const double dO = std::abs(answers[i].w - e.obscurance);
        double dW = 0;
        for (int c = 0; c < 3; ++c)
          dW = std::max(dW, double(std::abs(answers[i][c] - e.transfer[c])));
        ++compared;
        occluded += e.obscurance < 1;
        if (dO < 1e-6 && dW < 1e-5) {
          worst = std::max({worst, dO, dW});
          continue;
        }
        // Single precision on both sides: a test point within a few ulps of
        // the surface may land on the other side. That changes one sample.
        ++flipped;
        EXPECT_LE(dO, 1.0 / n + 1e-6) << "n " << n << " m " << steps << " query " << i;
      }
    }
  }
  std::printf(
      "obscurance parity over %zu points (%zu with O < 1): %zu with one containment test decided "
      "differently; otherwise worst |O|,|W| difference %.3g\n",
      compared, occluded, flipped, worst);
  EXPECT_GT(occluded, compared / 4) << "the terrain must occlude many of the points";
  for (size_t count : perSet) EXPECT_GE(count, compared / 20) << "every set must be compared";
  EXPECT_LT(flipped, compared / 200) << "more than 0.5% of points differ";
}

}  // namespace
}  // namespace aal
