// shade() of shaders/shading.glsl agrees with terrain/light/shading.h on the device.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/vec4.hpp>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/commands.h"
#include "aperture/engine/vk/compute.h"
#include "aperture/engine/vk/descriptors.h"
#include "aperture/engine/vk/image.h"
#include "aperture/shaders/config.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/cap_table.h"
#include "aperture/terrain/light/horizon_moments.h"
#include "aperture/terrain/light/shading.h"
#include "aperture/tests/engine/cap_table_image.h"
#include "aperture/tests/engine/vulkan_test.h"

namespace aal {
namespace {

struct Query {  // mirrors shading_parity.comp
  glm::vec4 albedoMode, normal, bentAperture, sunRadius, sunIrradiance, skyRadiance, transfer;
};
static_assert(sizeof(Query) == 7 * 16, "std430 layout");

glm::vec3 randomUnitAbove(std::mt19937& rng, float minZ) {
  std::normal_distribution<float> n;
  for (;;) {
    const glm::vec3 v = glm::normalize(glm::vec3(n(rng), n(rng), n(rng)));
    if (v.z >= minZ) return v;
  }
}

class ShadingParity : public VulkanTest {
 protected:
  // shade() of the GLSL for every query, with the exact mode's cap table made
  // for `table`'s sun radius bound (shaders/cap_table.glsl).
  std::vector<glm::vec4> shadeOnDevice(const std::vector<Query>& queries,
                                       const CapIntersectionTable& table) {
    const uint32_t count = static_cast<uint32_t>(queries.size());
    Buffer input(device(), count * sizeof(Query), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryIntent::Upload);
    Buffer output(device(), count * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                  MemoryIntent::Readback);
    input.write(queries.data(), count * sizeof(Query));
    const Image image = test::capTableImage(device(), table);
    const Sampler sampler(device(), VK_FILTER_LINEAR);
    {
      const ComputePipeline pipeline(device(), "shading_parity.comp", sizeof(uint32_t));
      submitAndWait(device(), [&](VkCommandBuffer cmd) {
        pipeline.record(
            cmd,
            DescriptorWrites().buffer(0, input).buffer(1, output).image(2, image.view(),
                                                                        sampler.handle()),
            &count, (count + AAL_SHADING_PARITY_GROUP_SIZE - 1) / AAL_SHADING_PARITY_GROUP_SIZE);
      });
    }
    std::vector<glm::vec4> answers(count);
    output.read(answers.data(), count * sizeof(glm::vec4));
    return answers;
  }

  // One float per query from a compute shader that reads the queries at
  // binding 0 and writes its answers at binding 1 (the horizon twins).
  template <class Q, class Answer = float>
  std::vector<Answer> floatsOnDevice(const char* shader, const std::vector<Q>& queries) {
    const uint32_t count = static_cast<uint32_t>(queries.size());
    Buffer input(device(), count * sizeof(Q), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                 MemoryIntent::Upload);
    Buffer output(device(), count * sizeof(Answer), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                  MemoryIntent::Readback);
    input.write(queries.data(), count * sizeof(Q));
    {
      const ComputePipeline pipeline(device(), shader, sizeof(uint32_t));
      submitAndWait(device(), [&](VkCommandBuffer cmd) {
        pipeline.record(
            cmd, {&input, &output}, &count,
            (count + AAL_SHADING_PARITY_GROUP_SIZE - 1) / AAL_SHADING_PARITY_GROUP_SIZE);
      });
    }
    std::vector<Answer> answers(count);
    output.read(answers.data(), count * sizeof(Answer));
    return answers;
  }
};

Query queryOf(const ShadingInputs& in, int mode) {
  return {glm::vec4(in.albedo, float(mode)),
          glm::vec4(in.normal, in.sunHorizonVarianceRad2),
          glm::vec4(in.bentNormal, in.apertureRad),
          glm::vec4(in.sunDirection, in.sunRadiusRad),
          glm::vec4(in.sunIrradiance, in.sunEdgeSpreadRad),
          glm::vec4(in.skyRadiance, 0),
          glm::vec4(in.transfer, in.sunHorizonRad)};
}

TEST_F(ShadingParity, GlslShadeMatchesCppForEveryMode) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Query> queries;
  std::vector<ShadingInputs> inputs;
  std::vector<ShadingMode> modes;
  // The exact mode reads the cap table made for the frame's sun: the default
  // one here (the radius of the closed-form cases; random suns in the other
  // modes), other radii in the test below.
  const CapIntersectionTable table = makeCapIntersectionTable(ShadingInputs{}.sunRadiusRad);
  const auto add = [&](ShadingInputs in, int mode) {
    if (mode == AAL_MODE_EXACT) in.sunRadiusRad = table.lightRadiusRad;
    inputs.push_back(in);
    modes.push_back(static_cast<ShadingMode>(mode));
    queries.push_back(queryOf(in, mode));
  };
  // The cases of the CPU copy's closed-form tests (tests/terrain/light/shading_test.cpp):
  // apertures below pi/2 and bent normals 20 and 50 degrees from N, the sun
  // inside, on the rim of and outside the aperture. With those passing, this
  // test carries the closed forms over to the GLSL copy.
  for (const float r : {0.3f, 0.8f, 1.2f, 1.5707963f}) {
    for (const float tiltDeg : {20.0f, 50.0f}) {
      for (const float sunOffset : {-0.5f * r, 0.0f, 0.1f}) {
        for (const int mode : {AAL_MODE_APPROX, AAL_MODE_EXACT, AAL_MODE_DEBUG_SKY_FILL}) {
          const float beta = glm::radians(tiltDeg), d = r + sunOffset;
          ShadingInputs in;
          in.albedo = {0.3f, 0.5f, 0.7f};
          in.bentNormal = {std::sin(beta), 0, std::cos(beta)};
          in.apertureRad = r;
          const glm::vec3 across = glm::normalize(glm::vec3(-std::cos(beta), 1, std::sin(beta)));
          in.sunDirection = std::cos(d) * in.bentNormal + std::sin(d) * across;
          in.sunIrradiance = {100, 90, 80};
          in.skyRadiance = {5, 6, 9};
          in.transfer = {0.9f, 0.8f, 0.6f};
          add(in, mode);
        }
      }
    }
  }
  for (int mode = AAL_MODE_APPROX; mode <= AAL_MODE_HORIZON; ++mode) {
    for (int i = 0; i < 500; ++i) {
      ShadingInputs in;
      in.albedo = {unit(rng), unit(rng), unit(rng)};
      in.normal = randomUnitAbove(rng, 0.3f);
      in.bentNormal = glm::normalize(in.normal + 0.5f * randomUnitAbove(rng, 0.0f));
      in.apertureRad = 0.05f + 1.5f * unit(rng);
      // Suns near the aperture's rim half the time: the partial-shadow case.
      const glm::vec3 l = randomUnitAbove(rng, -0.1f);
      in.sunDirection =
          i % 2 ? l : glm::normalize(in.bentNormal * std::cos(in.apertureRad) + l * 0.5f);
      in.sunRadiusRad = 0.00465f * (1.0f + 10.0f * unit(rng));
      in.sunIrradiance = {100 * unit(rng), 90 * unit(rng), 80 * unit(rng)};
      in.skyRadiance = {5 * unit(rng), 6 * unit(rng), 9 * unit(rng)};
      in.transfer = {unit(rng), unit(rng), unit(rng)};
      // Horizons within a few sun radii of the sun (partly hidden), or anywhere.
      const float elevation = std::asin(std::clamp(in.sunDirection.z, -1.0f, 1.0f));
      in.sunHorizonRad =
          i % 2 ? elevation + in.sunRadiusRad * (4.0f * unit(rng) - 2.0f) : 1.2f * unit(rng) - 0.1f;
      // A footprint's spread of the sun's distance from the edge in every
      // third input: none up to beyond the widening's limit.
      if (i % 3 == 1) in.sunEdgeSpreadRad = 0.04f * unit(rng);
      // A footprint's spread of horizons: none (one texel) a third of the
      // time, else up to a few sun radii.
      const float spread = i % 3 ? 4.0f * in.sunRadiusRad * unit(rng) : 0.0f;
      in.sunHorizonVarianceRad2 = spread * spread;
      add(in, mode);
    }
  }
  const uint32_t count = static_cast<uint32_t>(queries.size());
  const std::vector<glm::vec4> answers = shadeOnDevice(queries, table);
  double worst = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const glm::vec3 expected = shade(inputs[i], modes[i], &table);
    const float scale = std::max(1.0f, std::max({expected.r, expected.g, expected.b}));
    for (int c = 0; c < 3; ++c) {
      // Single precision on both sides; near the aperture rim the exact cap
      // formula's few-ulp differences scale with E_sun / A(r_s).
      EXPECT_NEAR(answers[i][c], expected[c], 2e-3f * scale)
          << "mode " << int(modes[i]) << " query " << i << " channel " << c;
      worst = std::max(worst, double(std::abs(answers[i][c] - expected[c]) / scale));
    }
  }
  std::printf("shading parity over %u inputs: worst relative difference %.3g\n", count, worst);
}

// The exact mode with larger suns, each with its own table, suns near the
// aperture's rim: the GLSL reads the table bound for the frame (a table of
// another radius, or the closed form in place of the table, would differ).
TEST_F(ShadingParity, ExactModeReadsTheTableOfTheFramesSun) {
  std::mt19937 rng(18);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (const float sun : {0.02f, 0.1f}) {
    const CapIntersectionTable table = makeCapIntersectionTable(sun);
    std::vector<Query> queries;
    std::vector<ShadingInputs> inputs;
    for (int i = 0; i < 1000; ++i) {
      ShadingInputs in;
      in.albedo = glm::vec3(0.3f);
      in.normal = randomUnitAbove(rng, 0.3f);
      in.bentNormal = glm::normalize(in.normal + 0.5f * randomUnitAbove(rng, 0.0f));
      in.apertureRad = 0.01f + 1.6f * unit(rng);
      const glm::vec3 across =
          glm::normalize(glm::cross(in.bentNormal, randomUnitAbove(rng, -1.0f)));
      const float d = in.apertureRad + sun * (3.0f * unit(rng) - 1.5f);
      in.sunDirection = glm::normalize(std::cos(d) * in.bentNormal + std::sin(d) * across);
      in.sunRadiusRad = sun;
      in.sunIrradiance = {100, 90, 80};
      in.skyRadiance = {5, 6, 9};
      inputs.push_back(in);
      queries.push_back(queryOf(in, AAL_MODE_EXACT));
    }
    const std::vector<glm::vec4> answers = shadeOnDevice(queries, table);
    double worst = 0;
    for (size_t i = 0; i < queries.size(); ++i) {
      const glm::vec3 expected = shade(inputs[i], ShadingMode::Exact, &table);
      const float scale = std::max(1.0f, std::max({expected.r, expected.g, expected.b}));
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(answers[i][c], expected[c], 2e-3f * scale) << "sun " << sun << " query " << i;
        worst = std::max(worst, double(std::abs(answers[i][c] - expected[c]) / scale));
      }
    }
    std::printf("exact shading with the %.3f rad sun's table: worst relative difference %.3g\n",
                sun, worst);
  }
}

// horizonAtAzimuth of shaders/horizon.glsl against terrain/io/horizon_map.h:
// random 8-bit and 4-bit codes, azimuths all round (and beyond a turn both
// ways).
TEST_F(ShadingParity, HorizonInterpolationMatchesCpp) {
  struct HorizonQuery {
    glm::vec4 codes[4], azimuth;
  };
  std::mt19937 rng(18);
  std::uniform_int_distribution<int> code(0, 255);
  std::uniform_real_distribution<float> azimuth(-7.0f, 14.0f);
  std::vector<HorizonQuery> queries;
  std::vector<std::array<uint8_t, kMaxHorizonDirections>> codes;
  std::vector<int> directions, bits;
  for (int i = 0; i < 8000; ++i) {
    const int b = i < 4000 ? 8 : 4;
    const int maxCode = (1 << b) - 1;
    std::array<uint8_t, kMaxHorizonDirections> c;
    for (uint8_t& v : c) v = uint8_t(code(rng) % (maxCode + 1));
    const int n = 4 * (1 + i % 4);  // 4, 8, 12, 16
    // Every stored direction exactly, then anywhere.
    const float a =
        i % 4000 < 256 ? float(i % 4000 / 4) * float(2 * std::numbers::pi / n) : azimuth(rng);
    codes.push_back(c);
    directions.push_back(n);
    bits.push_back(b);
    HorizonQuery q;
    for (int l = 0; l < 4; ++l) {
      q.codes[l] = glm::vec4(c[4 * l], c[4 * l + 1], c[4 * l + 2], c[4 * l + 3]) / float(maxCode);
    }
    q.azimuth = glm::vec4(a, float(n), float(b), 0);
    queries.push_back(q);
  }
  const uint32_t count = static_cast<uint32_t>(queries.size());
  const std::vector<float> answers = floatsOnDevice("horizon_parity.comp", queries);
  double worst = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const float expected =
        horizonAtAzimuth(codes[i].data(), directions[i], queries[i].azimuth.x, bits[i]);
    // Float rounding of the azimuth's position between directions.
    EXPECT_NEAR(answers[i], expected, 1e-5f)
        << "query " << i << " azimuth " << queries[i].azimuth.x << " bits " << bits[i];
    worst = std::max(worst, double(std::abs(answers[i] - expected)));
  }
  std::printf("horizon interpolation parity over %u inputs: worst %.3g rad\n", count, worst);
}

// horizonPairSpread and horizonMomentSunFraction of shaders/horizon_moments.glsl
// against terrain/light/horizon_moments.h and shading.h: random moments of
// two directions (a spread of none to a few degrees, second moments a hair
// below the mean's square too, which must read as no spread), weights,
// suns near the mean and anywhere, sun radii of the sun's to ten times it.
TEST_F(ShadingParity, HorizonMomentsMatchCpp) {
  struct MomentQuery {  // mirrors horizon_moments_parity.comp
    glm::vec4 moments, sun;
  };
  std::mt19937 rng(19);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<MomentQuery> queries;
  std::vector<std::array<HorizonMoments, 2>> moments;
  for (int i = 0; i < 20000; ++i) {
    std::array<HorizonMoments, 2> m;
    for (HorizonMoments& d : m) {
      d.mean = 0.4f * unit(rng) - 0.03f;
      const float spread = i % 4 ? 0.05f * unit(rng) * unit(rng) : 0.0f;
      d.second = d.mean * d.mean + spread * spread;
      if (i % 8 == 0) d.second = d.mean * d.mean * (1.0f - 1.0f / 2048.0f);
    }
    const float w = i % 5 ? unit(rng) : float(i % 2);
    const float radius = 0.00465f * (1.0f + 9.0f * unit(rng) * unit(rng));
    const float mean = (1.0f - w) * m[0].mean + w * m[1].mean;
    const float elevation = i % 2 ? mean + 0.02f * (2.0f * unit(rng) - 1.0f) : 0.4f * unit(rng);
    moments.push_back(m);
    queries.push_back({glm::vec4(m[0].mean, m[1].mean, m[0].second, m[1].second),
                       glm::vec4(1.0f - w, w, elevation, radius)});
  }
  const std::vector<glm::vec4> answers =
      floatsOnDevice<MomentQuery, glm::vec4>("horizon_moments_parity.comp", queries);
  double worstMean = 0, worstVariance = 0, worstFraction = 0;
  for (size_t i = 0; i < queries.size(); ++i) {
    const glm::vec4& q = queries[i].sun;
    const HorizonSpread spread = horizonPairSpread(moments[i][0], moments[i][1], {q.x, q.y});
    const float fraction = horizonMomentSunFraction(q.z, spread.mean, spread.variance, q.w);
    // Single precision on both sides; the fraction's slope is at most
    // 2 / (pi r) per rad of horizon, so a few ulps of the mean near the sun
    // move it by ~1e-4 for the smallest sun.
    ASSERT_NEAR(answers[i].x, spread.mean, 1e-6f) << i;
    ASSERT_NEAR(answers[i].y, spread.variance, 1e-7f) << i;
    ASSERT_NEAR(answers[i].z, fraction, 1e-3f) << i;
    worstMean = std::max(worstMean, double(std::abs(answers[i].x - spread.mean)));
    worstVariance = std::max(worstVariance, double(std::abs(answers[i].y - spread.variance)));
    worstFraction = std::max(worstFraction, double(std::abs(answers[i].z - fraction)));
  }
  std::printf(
      "horizon moments parity over %zu inputs: worst mean %.3g rad, variance %.3g rad^2, "
      "sun fraction %.3g\n",
      queries.size(), worstMean, worstVariance, worstFraction);
}

}  // namespace
}  // namespace aal
