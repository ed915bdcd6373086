// The GLSL cap functions (shaders/caps.glsl) agree with the C++ ones
// (terrain/light/caps.h) when run on the device.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/engine/vk/descriptors.h"
#include "aperture/engine/vk/image.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/light/cap_table.h"
#include "aperture/terrain/light/caps.h"
#include "aperture/tests/engine/cap_table_image.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

constexpr double kPi = std::numbers::pi;

struct CapQuery {  // mirrors caps_parity.comp
  glm::vec4 radii;
  glm::vec4 bentNormal;
  glm::vec4 lightDir;
};
struct CapAnswer {
  glm::vec4 areas;
  glm::vec4 centroid;
};
static_assert(sizeof(CapQuery) == 48 && sizeof(CapAnswer) == 32, "std430 layout");

glm::vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<float> n;
  return glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
}

std::vector<CapQuery> makeQueries() {
  std::vector<CapQuery> queries;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<float> angle(0.0f, float(kPi));
  auto add = [&](float r0, float r1, float d) {
    // w: the light's visible fraction for visibleLightCentroid (r1 is the light).
    const float fraction = float(queries.size() % 5) / 4.0f;
    queries.push_back(
        {{r0, r1, d, fraction}, glm::vec4(randomUnit(rng), 0), glm::vec4(randomUnit(rng), 0)});
  };
  for (int i = 0; i < 4000; ++i) add(angle(rng), angle(rng), angle(rng));
  // Sun-sized caps against apertures of every size: the renderer's case.
  for (int i = 0; i < 500; ++i) {
    const float sun = 0.00465f * (1.0f + 4.0f * float(i % 5));
    const float aperture = angle(rng);
    std::uniform_real_distribution<float> near(std::max(0.0f, aperture - 2 * sun),
                                               aperture + 2 * sun);
    add(sun, aperture, std::min(near(rng), float(kPi)));
  }
  // Boundaries and degenerate inputs.
  const float pi = float(kPi);
  for (float r : {0.0f, 0.01f, 0.5f, pi / 2, 2.5f, pi}) {
    for (float s : {0.0f, 0.3f, pi / 2, 3.0f, pi}) {
      for (float d : {0.0f, std::abs(r - s), r + s, 2 * pi - r - s, pi / 2, pi}) {
        if (d >= 0.0f && d <= pi) add(r, s, d);
      }
    }
  }
  return queries;
}

class CapsParity : public VulkanTest {};

TEST_F(CapsParity, GlslMatchesCpp) {
  const std::vector<CapQuery> queries = makeQueries();
  const size_t count = queries.size();
  Buffer input(device(), count * sizeof(CapQuery), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
               MemoryIntent::Upload);
  Buffer output(device(), count * sizeof(CapAnswer), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                MemoryIntent::Readback);
  input.write(queries.data(), count * sizeof(CapQuery));

  {
    const ComputePipeline pipeline(device(), "caps_parity.comp", sizeof(uint32_t));
    const uint32_t n = static_cast<uint32_t>(count);
    const uint32_t groups = (n + AAL_CAPS_PARITY_GROUP_SIZE - 1) / AAL_CAPS_PARITY_GROUP_SIZE;
    submitAndWait(device(), [&](VkCommandBuffer cmd) {
      pipeline.record(cmd, {&input, &output}, &n, groups);
    });
  }
  std::vector<CapAnswer> answers(count);
  output.read(answers.data(), count * sizeof(CapAnswer));

  double worstExact = 0, worstApprox = 0, worstRelative = 0;
  for (size_t i = 0; i < count; ++i) {
    const glm::vec4& q = queries[i].radii;
    const CapAnswer& a = answers[i];
    EXPECT_NEAR(a.areas.x, capArea(q.x), 1e-6 * capArea(q.x) + 1e-12) << i;
    // Single precision against double: a few float ulps of the largest term,
    // and for small caps a small fraction of the smaller cap.
    const double exact = capIntersectionExact(q.x, q.y, q.z);
    const double smaller = capArea(std::min(q.x, q.y));
    EXPECT_NEAR(a.areas.y, exact, std::min(1e-5 * 4 * kPi, 1e-3 * smaller + 1e-9))
        << "exact r0=" << q.x << " r1=" << q.y << " d=" << q.z;
    if (smaller > 0) worstRelative = std::max(worstRelative, std::abs(a.areas.y - exact) / smaller);
    // Same float formula on both sides: only cos() rounding differs.
    const float approx = capIntersectionApprox(q.x, q.y, q.z);
    EXPECT_NEAR(a.areas.z, approx, 1e-5 * 4 * kPi)
        << "approx r0=" << q.x << " r1=" << q.y << " d=" << q.z;
    const glm::vec3 c = visibleLightCentroid(glm::vec3(queries[i].bentNormal),
                                             glm::vec3(queries[i].lightDir), q.z, q.y, q.w);
    EXPECT_LT(glm::length(glm::vec3(a.centroid) - c), 1e-5f) << i;
    worstExact = std::max(worstExact, std::abs(a.areas.y - exact));
    worstApprox = std::max(worstApprox, double(std::abs(a.areas.z - approx)));
  }
  RecordProperty("worst_exact_sr", std::to_string(worstExact));
  RecordProperty("worst_approx_sr", std::to_string(worstApprox));
  std::printf(
      "GLSL vs C++ over %zu triples: worst exact %.3g sr (%.3g of the smaller cap), "
      "worst approx %.3g sr\n",
      count, worstExact, worstRelative, worstApprox);
}

// The exact mode's table (shaders/cap_table.glsl) read on the device for
// several sun radii, the thinnest the tools allow (0.01 degrees) to the
// widest (20 degrees): against its C++ twin (same texels, the device's
// bilinear filter) and against the closed form, which it must follow to
// 1e-3 of the smaller cap's area (docs/caps.md).
TEST_F(CapsParity, CapTableLookupMatchesCppAndTheClosedForm) {
  for (const float sun : {0.000174533f, 0.004653f, 0.02f, 0.1f, 0.349066f}) {
    const CapIntersectionTable table = makeCapIntersectionTable(sun);
    std::vector<glm::vec2> queries;
    // Every aperture size, dense where the sun is partly hidden: the band
    // |r_a - r_s| < d < r_a + r_s (and a little beyond it on both sides).
    for (int a = 0; a <= 400; ++a) {
      const float ra =
          a < 200 ? 3.0f * sun * float(a) / 200.0f : float(kPi) * float(a - 200) / 200.0f;
      const float lo = std::max(0.0f, std::abs(ra - sun) - 0.1f * sun);
      const float hi = std::min(float(kPi), ra + sun + 0.1f * sun);
      for (int k = 0; k <= 60; ++k) queries.push_back({ra, lo + (hi - lo) * float(k) / 60.0f});
      for (int k = 0; k <= 8; ++k) queries.push_back({ra, float(kPi) * float(k) / 8.0f});
    }
    const uint32_t count = static_cast<uint32_t>(queries.size());
    Buffer input(device(), count * sizeof(glm::vec2), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryIntent::Upload);
    Buffer output(device(), count * sizeof(float), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                  MemoryIntent::Readback);
    input.write(queries.data(), count * sizeof(glm::vec2));
    const Image image = test::capTableImage(device(), table);
    const Sampler sampler(device(), VK_FILTER_LINEAR);
    {
      const ComputePipeline pipeline(device(), "cap_table_parity.comp", 2 * sizeof(uint32_t));
      const struct {
        uint32_t count;
        float sun;
      } push{count, sun};
      submitAndWait(device(), [&](VkCommandBuffer cmd) {
        pipeline.record(cmd,
                        DescriptorWrites().buffer(0, input).buffer(1, output).image(
                            2, image.view(), sampler.handle()),
                        &push,
                        (count + AAL_CAPS_PARITY_GROUP_SIZE - 1) / AAL_CAPS_PARITY_GROUP_SIZE);
      });
    }
    std::vector<float> answers(count);
    output.read(answers.data(), count * sizeof(float));
    double worstTwin = 0, worstExact = 0;
    for (uint32_t i = 0; i < count; ++i) {
      const float ra = queries[i].x, d = queries[i].y;
      const double smaller = capArea(std::min<double>(ra, sun));
      const double twin = capIntersectionFromTable(table, ra, d);
      const double exact = capIntersectionExact(ra, sun, d);
      // The device filters with its own weights (and float rounding of the
      // coordinates): a small part of the table's error budget.
      EXPECT_NEAR(answers[i], twin, 1e-4 * smaller + 1e-6 * capArea(sun))
          << "sun " << sun << " r_a " << ra << " d " << d;
      EXPECT_NEAR(answers[i], exact, 1e-3 * smaller + 1e-6 * capArea(sun))
          << "sun " << sun << " r_a " << ra << " d " << d;
      if (smaller > 0) {
        worstTwin = std::max(worstTwin, std::abs(answers[i] - twin) / smaller);
        worstExact = std::max(worstExact, std::abs(answers[i] - exact) / smaller);
      }
    }
    std::printf(
        "cap table on the device, sun %.6f rad, %u pairs: worst vs C++ twin %.3g, vs closed "
        "form %.3g of the smaller cap\n",
        sun, count, worstTwin, worstExact);
  }
}

}  // namespace
}  // namespace aal
