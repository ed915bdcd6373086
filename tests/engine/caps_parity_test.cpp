// The GLSL cap functions (shaders/caps.glsl) agree with the C++ ones
// (terrain/caps.h) when run on the device.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include "buffer.h"
#include "caps.h"
#include "commands.h"
#include "compute.h"
#include "config.h"
#include "vulkan_test.h"

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
    const ComputePipeline pipeline(device(), "caps_parity.comp", 2, sizeof(uint32_t));
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

}  // namespace
}  // namespace aal
