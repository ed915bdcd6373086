// The GLSL LOD morph (shaders/lod.glsl) agrees with its C++ twin
// (terrain/view/lod_patch.h) when run on the device; at and beyond the morph
// range's end both put the vertex exactly on the coarser grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/view/lod_patch.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

struct LodQuery {  // mirrors lod_parity.comp
  LodPatch patch;
  glm::vec4 point;  // vertex index, distance (m), DEM size (texels)
};
static_assert(sizeof(LodQuery) == 48, "std430 layout");

class LodParity : public VulkanTest {};

TEST_F(LodParity, GlslMorphMatchesCpp) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<LodQuery> queries;
  for (int i = 0; i < 20000; ++i) {
    const int level = int(rng() % 11);
    const float quad = float(1 << level), nodeTexels = quad * kLodPatchQuads;
    LodQuery q;
    q.patch.node = {nodeTexels * float(rng() % 8), nodeTexels * float(rng() % 8), quad, level};
    const float end = 500.0f * quad * (1.0f + unit(rng)), start = end * (0.5f + 0.4f * unit(rng));
    q.patch.morph = {start, end, 0, 0};
    // Distances before, inside and beyond the morph range; some at its ends.
    float distance = (0.2f + 1.6f * unit(rng)) * end;
    if (i % 10 == 0) distance = end;
    if (i % 10 == 1) distance = start;
    // DEM sizes that cut some patches (their overhang is clamped).
    const float dem = 2.0f + float(rng() % 9) * nodeTexels * unit(rng);
    q.point = {float(rng() % kLodPatchVertices), distance, dem, dem + 3.0f};
    if (i % 7 == 0) q.patch.morph = {kLodNoMorph, 2 * kLodNoMorph, 0, 0};
    queries.push_back(q);
  }
  const uint32_t count = static_cast<uint32_t>(queries.size());
  Buffer input(device(), count * sizeof(LodQuery), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               MemoryIntent::Upload);
  input.write(queries.data(), count * sizeof(LodQuery));
  Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryIntent::Readback);
  const ComputePipeline pipeline(device(), "lod_parity.comp", sizeof(uint32_t));
  const uint32_t groups = (count + AAL_LOD_PARITY_GROUP_SIZE - 1) / AAL_LOD_PARITY_GROUP_SIZE;
  submitAndWait(device(), [&](VkCommandBuffer cmd) {
    pipeline.record(cmd, {&input, &output}, &count, groups);
  });
  std::vector<glm::vec4> answers(count);
  output.read(answers.data(), count * sizeof(glm::vec4));

  // Both sides evaluate the same single-precision expressions; only the
  // division in the morph factor may round differently on the device (not
  // necessarily correctly rounded): k within a few ulps, and the texel within
  // that times the quad size (measured worst printed below). Where k is
  // exactly 0 or 1 (clamped) the results must be identical: that is what
  // makes neighbouring patches meet.
  double worstK = 0, worstTexel = 0;
  int ends = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const LodQuery& q = queries[i];
    constexpr int stride = kLodPatchQuads + 1;
    const int vertex = int(q.point.x);
    const glm::vec2 grid(vertex % stride, vertex / stride);
    const float k = lodMorphFactor(q.point.y, glm::vec2(q.patch.morph));
    const glm::vec2 texel =
        lodPatchTexel(q.patch, lodMorphGridPoint(grid, k), glm::vec2(q.point.z, q.point.w));
    const glm::vec4 gpu = answers[i];
    if (k == 0.0f || k == 1.0f) {
      ++ends;
      ASSERT_EQ(gpu.z, k) << i;
      ASSERT_EQ(gpu.x, texel.x) << i;
      ASSERT_EQ(gpu.y, texel.y) << i;
      if (k == 1.0f) {
        // On the coarser level's grid (or clamped to the DEM's edge).
        const glm::vec2 fromNode = (texel - glm::vec2(q.patch.node)) / (2.0f * q.patch.node.z);
        EXPECT_TRUE((fromNode.x == std::floor(fromNode.x) || texel.x == q.point.z - 1) &&
                    (fromNode.y == std::floor(fromNode.y) || texel.y == q.point.w - 1))
            << i;
      }
    } else {
      // A different k moves the texel by quad size x dk; adding the node's
      // corner may round one ulp of the texel apart.
      const double dk = std::abs(double(gpu.z) - k);
      worstK = std::max(worstK, dk);
      for (int c = 0; c < 2; ++c) {
        const float t = std::abs(texel[c]);
        const double ulp = std::nextafter(t, INFINITY) - t;
        const double excess = std::abs(double(gpu[c]) - texel[c]) - q.patch.node.z * dk;
        worstTexel = std::max(worstTexel, excess / ulp);
      }
    }
  }
  std::printf(
      "%d queries at the ends of the range identical; inside it worst |dk| %.3g, "
      "worst texel difference beyond quad x dk %.3g ulp\n",
      ends, worstK, worstTexel);
  EXPECT_GT(ends, 5000);
  EXPECT_LT(worstK, 4e-7);
  EXPECT_LE(worstTexel, 1.0);
}

}  // namespace
}  // namespace aal
