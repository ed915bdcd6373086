// The Frame uniform block of shaders/frame.glsl and its C++ twin
// (engine/frame_uniforms.h) put every member at the same offset: every
// 4-byte word of the uploaded block gets its own bit pattern, and a shader
// reads the members back by name (shaders/frame_layout_parity.comp).
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <vector>

#include "aperture/engine/frame_uniforms.h"
#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

// The words a member of `components` 4-byte values at `offset` occupies.
void addMember(std::vector<uint32_t>& words, size_t offset, int components) {
  for (int c = 0; c < components; ++c) words.push_back(uint32_t(offset / 4 + c));
}

// The words of the members in the order frame_layout_parity.comp reads them.
std::vector<uint32_t> memberWords() {
  std::vector<uint32_t> w;
#define AAL_MEMBER(name, components) addMember(w, offsetof(FrameUniforms, name), components)
  AAL_MEMBER(viewProj, 16);
  AAL_MEMBER(invViewProj, 16);
  AAL_MEMBER(previousViewProj, 16);
  AAL_MEMBER(cameraPos, 3);
  AAL_MEMBER(pixelAngle, 1);
  AAL_MEMBER(sunDirection, 3);
  AAL_MEMBER(sunRadiusRad, 1);
  AAL_MEMBER(sunIrradiance, 3);
  AAL_MEMBER(hazeDensityPerM, 1);
  AAL_MEMBER(skyRadiance, 3);
  AAL_MEMBER(exposure, 1);
  AAL_MEMBER(demSize, 2);
  AAL_MEMBER(cellSizeM, 2);
  AAL_MEMBER(minHeightM, 1);
  AAL_MEMBER(maxHeightM, 1);
  AAL_MEMBER(waterLevelM, 1);
  AAL_MEMBER(hasWater, 1);
  AAL_MEMBER(albedoValue, 3);
  AAL_MEMBER(backgroundAlpha, 1);
  AAL_MEMBER(baseAlbedo, 3);
  AAL_MEMBER(baseBottomM, 1);
  AAL_MEMBER(extent, 2);
  AAL_MEMBER(previousExtent, 2);
  AAL_MEMBER(rawOutput, 1);
  AAL_MEMBER(historySubset, 1);
  AAL_MEMBER(historyValid, 1);
  AAL_MEMBER(obscuranceRadiusM, 1);
  AAL_MEMBER(obscuranceSamples, 1);
  AAL_MEMBER(obscuranceSteps, 1);
  AAL_MEMBER(obscuranceInterleaved, 1);
  AAL_MEMBER(obscurancePixelSize, 1);
  AAL_MEMBER(tileCoreSize, 2);
  AAL_MEMBER(tileCount, 2);
  AAL_MEMBER(tileImageSize, 2);
  AAL_MEMBER(tileBorder, 1);
  AAL_MEMBER(heightLayersPerPage, 1);
  AAL_MEMBER(apertureLayersPerPage, 1);
  AAL_MEMBER(albedoLayersPerPage, 1);
  AAL_MEMBER(footprintScale, 1);
  AAL_MEMBER(sky, 7 * 4);
  AAL_MEMBER(horizonWeights, 2);
#undef AAL_MEMBER
  return w;
}

// Word i of the block: near 1.0f as a float (no denormals, no NaN), a
// different integer for every i.
uint32_t pattern(uint32_t i) {
  return 0x3F800000u + i;
}

class FrameLayout : public VulkanTest {};

TEST_F(FrameLayout, GlslReadsEveryMemberWhereCppWritesIt) {
  const std::vector<uint32_t> expected = memberWords();
  // Every word but the padding before the sky (one word) belongs to one member.
  const std::set<uint32_t> distinct(expected.begin(), expected.end());
  EXPECT_EQ(distinct.size(), expected.size());
  EXPECT_EQ(distinct.size(), sizeof(FrameUniforms) / 4 - 1);

  std::vector<uint32_t> block(sizeof(FrameUniforms) / 4);
  for (uint32_t i = 0; i < block.size(); ++i) block[i] = pattern(i);
  Buffer uniforms(device(), sizeof(FrameUniforms), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                  MemoryIntent::Upload);
  uniforms.write(block.data(), sizeof(FrameUniforms));
  Buffer words(device(), expected.size() * sizeof(uint32_t), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               MemoryIntent::Readback);
  const ComputePipeline pipeline(device(), "frame_layout_parity.comp", 0);
  submitAndWait(device(), [&](VkCommandBuffer cmd) {
    pipeline.record(cmd, DescriptorWrites().buffer(0, uniforms).buffer(1, words), nullptr, 1);
  });
  std::vector<uint32_t> read(expected.size());
  words.read(read.data(), read.size() * sizeof(uint32_t));
  for (size_t k = 0; k < expected.size(); ++k) {
    EXPECT_EQ(read[k], pattern(expected[k])) << "value " << k << " read by the shader: C++ word "
                                             << expected[k] << " (byte " << 4 * expected[k] << ")";
  }
}

}  // namespace
}  // namespace aal
