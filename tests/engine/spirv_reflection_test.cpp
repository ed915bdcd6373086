// The descriptor bindings read from SPIR-V (engine/vk/spirv_reflection.h)
// against an independent reference: glslang's own view of the GLSL each
// shipped module was compiled from (every declared resource in its syntax
// tree, and its reflection of the live ones); hand-checked expectations for
// a few pipelines; malformed modules.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <glslang/MachineIndependent/localintermediate.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>

#include "aperture/engine/vk/buffer.h"
#include "aperture/engine/vk/descriptors.h"
#include "aperture/engine/vk/embedded_shaders.h"
#include "aperture/engine/vk/shader.h"
#include "aperture/engine/vk/spirv_reflection.h"
#include "aperture/tests/engine/vulkan_test.h"

#ifndef AAL_SHADER_VARIANT_DIR
#define AAL_SHADER_VARIANT_DIR ""
#endif

namespace aal {
namespace {

namespace fs = std::filesystem;

std::string readText(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("cannot read " + path.string());
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

// The GLSL a module was built from: shaders/NAME, or the variant stub that
// cmake/Shaders.cmake wrote for it.
fs::path sourceOf(const std::string& name) {
  const fs::path plain = fs::path(AAL_TEST_SOURCE_DIR) / "shaders" / name;
  if (fs::exists(plain)) return plain;
  return fs::path(AAL_SHADER_VARIANT_DIR) / name;
}

// #include "x" from shaders/, as glslangValidator -I does.
class ShaderIncluder : public glslang::TShader::Includer {
 public:
  IncludeResult* includeLocal(const char* header, const char*, size_t) override {
    return read(header);
  }
  IncludeResult* includeSystem(const char* header, const char*, size_t) override {
    return read(header);
  }
  void releaseInclude(IncludeResult* result) override {
    if (!result) return;
    delete static_cast<std::string*>(result->userData);
    delete result;
  }

 private:
  static IncludeResult* read(const char* header) {
    const fs::path path = fs::path(AAL_TEST_SOURCE_DIR) / "shaders" / header;
    if (!fs::exists(path)) return nullptr;
    auto* text = new std::string(readText(path));
    return new IncludeResult(path.string(), text->data(), text->size(), text);
  }
};

struct Stage {
  EShLanguage language;
  VkShaderStageFlags flag;
};

Stage stageOf(const std::string& name) {
  const std::string ext = fs::path(name).extension().string();
  if (ext == ".vert") return {EShLangVertex, VK_SHADER_STAGE_VERTEX_BIT};
  if (ext == ".frag") return {EShLangFragment, VK_SHADER_STAGE_FRAGMENT_BIT};
  if (ext == ".comp") return {EShLangCompute, VK_SHADER_STAGE_COMPUTE_BIT};
  throw std::runtime_error("no stage for " + name);
}

// The descriptor type Vulkan gives a GLSL resource (the Vulkan GLSL
// extension, GL_KHR_vulkan_glsl), from glslang's type of it.
VkDescriptorType descriptorTypeOf(const glslang::TType& type) {
  if (type.getBasicType() == glslang::EbtBlock) {
    return type.getQualifier().storage == glslang::EvqBuffer ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                                             : VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  }
  if (type.getBasicType() == glslang::EbtSampler) {
    const glslang::TSampler& s = type.getSampler();
    if (s.isPureSampler()) return VK_DESCRIPTOR_TYPE_SAMPLER;
    if (s.isSubpass()) return VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT;
    if (s.isBuffer()) {
      return s.isImage() ? VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER
                         : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
    }
    if (s.isImage()) return VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
    return s.isCombined() ? VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER
                          : VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE;
  }
  return VK_DESCRIPTOR_TYPE_MAX_ENUM;
}

DescriptorBinding bindingOf(const glslang::TType& type, VkShaderStageFlags stage) {
  const glslang::TQualifier& q = type.getQualifier();
  return {.set = q.hasSet() ? q.layoutSet : 0u,
          .binding = q.hasBinding() ? q.layoutBinding : ~0u,
          .type = descriptorTypeOf(type),
          .count = !type.isArray()         ? 1u
                   : type.isUnsizedArray() ? 0u
                                           : uint32_t(type.getCumulativeArraySize()),
          .stages = stage};
}

bool sameSlot(const DescriptorBinding& a, const DescriptorBinding& b) {
  return a.set == b.set && a.binding == b.binding;
}

// glslang's view of one shader: every resource it declares, from the
// linker objects of its syntax tree, and the live ones from its reflection.
struct GlslangView {
  std::vector<DescriptorBinding> declared, live;
};

GlslangView glslangView(const std::string& name) {
  static const bool initialised = glslang::InitializeProcess();
  EXPECT_TRUE(initialised);
  const Stage stage = stageOf(name);
  const std::string text = readText(sourceOf(name));
  const char* source = text.c_str();
  glslang::TShader shader(stage.language);
  shader.setStrings(&source, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, stage.language, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_2);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_5);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
  ShaderIncluder includer;
  if (!shader.parse(GetDefaultResources(), 100, false, messages, includer)) {
    throw std::runtime_error(name + ": " + shader.getInfoLog());
  }
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages) || !program.buildReflection()) {
    throw std::runtime_error(name + ": " + program.getInfoLog());
  }

  GlslangView view;
  const glslang::TIntermAggregate* root =
      program.getIntermediate(stage.language)->getTreeRoot()->getAsAggregate();
  for (TIntermNode* node : root->getSequence()) {
    const glslang::TIntermAggregate* group = node->getAsAggregate();
    if (!group || group->getOp() != glslang::EOpLinkerObjects) continue;
    for (TIntermNode* object : group->getSequence()) {
      const glslang::TType& type = object->getAsTyped()->getType();
      const glslang::TStorageQualifier storage = type.getQualifier().storage;
      if ((storage != glslang::EvqUniform && storage != glslang::EvqBuffer) ||
          type.getQualifier().isPushConstant()) {
        continue;
      }
      const DescriptorBinding b = bindingOf(type, stage.flag);
      const bool seen = std::any_of(view.declared.begin(), view.declared.end(),
                                    [&](const DescriptorBinding& d) { return d == b; });
      if (!seen) view.declared.push_back(b);
    }
  }
  std::sort(view.declared.begin(), view.declared.end(),
            [](const DescriptorBinding& a, const DescriptorBinding& b) {
              return a.set != b.set ? a.set < b.set : a.binding < b.binding;
            });
  // (A reflected block's type need not carry its binding; getBinding does.)
  const auto live = [&](const glslang::TObjectReflection& object) {
    if (object.getType()->getQualifier().isPushConstant()) return;
    DescriptorBinding b = bindingOf(*object.getType(), stage.flag);
    b.binding = static_cast<uint32_t>(object.getBinding());
    view.live.push_back(b);
  };
  for (int i = 0; i < program.getNumUniformBlocks(); ++i) live(program.getUniformBlock(i));
  for (int i = 0; i < program.getNumBufferBlocks(); ++i) live(program.getBufferBlock(i));
  for (int i = 0; i < program.getNumUniformVariables(); ++i) {
    if (program.getUniform(i).getType()->getBasicType() == glslang::EbtSampler) {
      live(program.getUniform(i));
    }
  }
  return view;
}

std::vector<std::string> shippedShaders() {
  std::vector<std::string> names;
  for (const EmbeddedShader& shader : embeddedShaders()) names.push_back(shader.name);
  return names;
}

TEST(SpirvReflection, EveryShippedShaderDeclaresWhatGlslangSees) {
  const std::vector<std::string> names = shippedShaders();
  // shaders/CMakeLists.txt builds 17 shaders and 20 variants.
  ASSERT_GE(names.size(), 37u);
  size_t bindings = 0;
  for (const std::string& name : names) {
    SCOPED_TRACE(name);
    const ShaderInterface mine = reflectShaderInterface(loadSpirv(name));
    const GlslangView reference = glslangView(name);
    EXPECT_EQ(mine.stages, stageOf(name).flag);
    EXPECT_EQ(mine.bindings, reference.declared);
    for (const DescriptorBinding& live : reference.live) {
      const auto it = std::find_if(mine.bindings.begin(), mine.bindings.end(),
                                   [&](const DescriptorBinding& b) { return sameSlot(b, live); });
      ASSERT_NE(it, mine.bindings.end()) << "live binding " << live.binding;
      EXPECT_EQ(it->type, live.type) << "binding " << live.binding;
    }
    bindings += mine.bindings.size();
  }
  EXPECT_GT(bindings, 100u);  // the comparison saw the terrain's twenty-odd per shader
}

ShaderInterface reflected(const std::string& name) {
  return reflectShaderInterface(loadSpirv(name));
}

constexpr VkShaderStageFlags kVertex = VK_SHADER_STAGE_VERTEX_BIT;
constexpr VkShaderStageFlags kFragment = VK_SHADER_STAGE_FRAGMENT_BIT;
constexpr VkShaderStageFlags kBoth = kVertex | kFragment;

// Checked by hand against shaders/terrain_textures.glsl, terrain_shading.glsl,
// patch_vertex.glsl and config.h: the frame (0), four pages of heights,
// apertures, albedo and slopes (1-16), the patches (17, read by the vertex
// shader), the cap table (18; the horizon mode's horizons come with the
// slopes).
TEST(SpirvReflection, TheTerrainPipelineMergesItsTwoStages) {
  const ShaderInterface merged =
      mergeShaderInterfaces({reflected("terrain.vert"), reflected("terrain.frag")});
  EXPECT_EQ(merged.stages, kBoth);
  ASSERT_EQ(merged.bindings.size(), 19u);
  EXPECT_EQ(merged.bindings[0], (DescriptorBinding{.set = 0,
                                                   .binding = 0,
                                                   .type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                                                   .count = 1,
                                                   .stages = kBoth}));
  for (uint32_t b = 1; b <= 16; ++b) {
    EXPECT_EQ(merged.bindings[b].binding, b);
    EXPECT_EQ(merged.bindings[b].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
    EXPECT_EQ(merged.bindings[b].stages, kBoth) << b;
  }
  EXPECT_EQ(merged.bindings[17], (DescriptorBinding{.set = 0,
                                                    .binding = 17,
                                                    .type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                                                    .count = 1,
                                                    .stages = kVertex}));
  EXPECT_EQ(merged.bindings[18],
            (DescriptorBinding{.set = 0,
                               .binding = 18,
                               .type = VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER,
                               .count = 1,
                               .stages = kFragment}));
}

// shaders/slopes.glsl: the heights sampled, a slope level written, the one below read.
TEST(SpirvReflection, TheSlopeShaderReadsASampledAndWritesAStorageImage) {
  const ShaderInterface slopes = reflected("slopes.comp");
  EXPECT_EQ(slopes.stages, VkShaderStageFlags(VK_SHADER_STAGE_COMPUTE_BIT));
  // The heights, sampled; the level written and the level below (whose
  // means the levels above 0 take), storage images.
  ASSERT_EQ(slopes.bindings.size(), 3u);
  EXPECT_EQ(slopes.bindings[0].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  EXPECT_EQ(slopes.bindings[1].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_EQ(slopes.bindings[1].binding, 1u);
  EXPECT_EQ(slopes.bindings[2].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_EQ(slopes.bindings[2].binding, 3u);
  // With the horizon pair (slopes_horizons.comp): also its codes, sampled,
  // the level below, and the second moments of the level and the level
  // below, storage images.
  const ShaderInterface horizons = reflected("slopes_horizons.comp");
  ASSERT_EQ(horizons.bindings.size(), 6u);
  EXPECT_EQ(horizons.bindings[0].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  EXPECT_EQ(horizons.bindings[1].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_EQ(horizons.bindings[2].type, VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER);
  for (uint32_t b = 3; b < 6; ++b) {
    EXPECT_EQ(horizons.bindings[b].type, VK_DESCRIPTOR_TYPE_STORAGE_IMAGE) << b;
    EXPECT_EQ(horizons.bindings[b].binding, b);
  }
}

// shaders/frame_layout_parity.comp: the frame's uniforms in, words out.
TEST(SpirvReflection, TheFrameLayoutShaderHasAUniformAndAStorageBuffer) {
  const ShaderInterface frame = reflected("frame_layout_parity.comp");
  ASSERT_EQ(frame.bindings.size(), 2u);
  EXPECT_EQ(frame.bindings[0].type, VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER);
  EXPECT_EQ(frame.bindings[1].type, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER);
}

TEST(SpirvReflection, OneBindingOfTwoTypesInTwoStagesIsAnError) {
  ShaderInterface a{.stages = kVertex, .bindings = {}}, b{.stages = kFragment, .bindings = {}};
  a.bindings.push_back({.set = 0,
                        .binding = 3,
                        .type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER,
                        .count = 1,
                        .stages = kVertex});
  b.bindings.push_back({.set = 0,
                        .binding = 3,
                        .type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                        .count = 1,
                        .stages = kFragment});
  EXPECT_THROW(mergeShaderInterfaces({a, b}), SpirvError);
  b.bindings[0].type = VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
  EXPECT_EQ(mergeShaderInterfaces({a, b}).bindings[0].stages, kBoth);
}

// The message of the SpirvError `words` give, or "" if they give none.
std::string errorOf(const std::vector<uint32_t>& words) {
  try {
    reflectShaderInterface(words);
  } catch (const SpirvError& e) {
    return e.what();
  }
  return "";
}

// Word offsets of a module's instructions.
std::vector<size_t> instructionStarts(const std::vector<uint32_t>& words) {
  std::vector<size_t> starts;
  for (size_t at = 5; at < words.size(); at += words[at] >> 16) starts.push_back(at);
  return starts;
}

TEST(SpirvReflection, MalformedModulesAreClearErrors) {
  const std::vector<uint32_t> good = loadSpirv("terrain.frag");
  ASSERT_EQ(errorOf(good), "");

  EXPECT_NE(errorOf({}).find("empty"), std::string::npos);
  EXPECT_NE(errorOf({good.begin(), good.begin() + 3}).find("truncated"), std::string::npos);

  std::vector<uint32_t> wrongMagic = good;
  wrongMagic[0] = 0xdeadbeef;
  EXPECT_NE(errorOf(wrongMagic).find("magic"), std::string::npos);

  // Cut inside an instruction of several words.
  const std::vector<size_t> starts = instructionStarts(good);
  const auto longOne = std::find_if(starts.begin() + starts.size() / 2, starts.end(),
                                    [&](size_t at) { return (good[at] >> 16) >= 3; });
  ASSERT_NE(longOne, starts.end());
  const std::vector<uint32_t> cut(good.begin(), good.begin() + *longOne + 2);
  EXPECT_NE(errorOf(cut).find("truncated"), std::string::npos) << errorOf(cut);

  std::vector<uint32_t> zeroCount = good;
  zeroCount[starts[3]] &= 0xffffu;
  EXPECT_NE(errorOf(zeroCount).find("word count 0"), std::string::npos);

  // The Binding decoration of one variable turned into OpNop (same length).
  std::vector<uint32_t> unbound = good;
  const auto binding = std::find_if(starts.begin(), starts.end(), [&](size_t at) {
    return (good[at] & 0xffffu) == 71 && good[at + 2] == 33;  // OpDecorate Binding
  });
  ASSERT_NE(binding, starts.end());
  unbound[*binding] &= 0xffff0000u;
  EXPECT_NE(errorOf(unbound).find("Binding"), std::string::npos) << errorOf(unbound);
}

TEST(SpirvReflection, EveryTruncationOrCorruptedWordIsAnErrorOrAnAnswerNeverACrash) {
  const std::vector<uint32_t> good = loadSpirv("obscurance_temporal_paged.frag");
  for (size_t n = 0; n < good.size(); ++n) {
    // (SpirvError is the only exception allowed out.)
    errorOf({good.begin(), good.begin() + static_cast<std::ptrdiff_t>(n)});
  }
  std::mt19937 rng(21);
  std::uniform_int_distribution<size_t> word(0, good.size() - 1);
  std::uniform_int_distribution<uint32_t> value;
  for (int i = 0; i < 2000; ++i) {
    std::vector<uint32_t> corrupted = good;
    corrupted[word(rng)] = i % 2 ? value(rng) : value(rng) & 0xffu;  // small ids and counts too
    errorOf(corrupted);
  }
}

TEST(SpirvReflection, EitherByteOrderReadsTheSame) {
  const std::vector<uint32_t> good = loadSpirv("composite_display.frag");
  std::vector<uint32_t> swapped(good.size());
  std::transform(good.begin(), good.end(), swapped.begin(), [](uint32_t w) {
    return (w >> 24) | ((w >> 8) & 0xff00u) | ((w << 8) & 0xff0000u) | (w << 24);
  });
  const ShaderInterface a = reflectShaderInterface(good), b = reflectShaderInterface(swapped);
  EXPECT_EQ(a.stages, b.stages);
  EXPECT_EQ(a.bindings, b.bindings);
  EXPECT_EQ(a.bindings.size(), 4u);
}

class ReflectedLayout : public VulkanTest {};

// Layouts cover set 0 only and no runtime-sized arrays; a write takes its
// type from the layout and must fit it.
TEST_F(ReflectedLayout, SetsOtherThanZeroAndWritesThatDoNotFitAreErrors) {
  ShaderInterface otherSet{.stages = VK_SHADER_STAGE_COMPUTE_BIT, .bindings = {}};
  otherSet.bindings.push_back({.set = 1,
                               .binding = 0,
                               .type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
                               .count = 1,
                               .stages = VK_SHADER_STAGE_COMPUTE_BIT});
  EXPECT_THROW(PipelineLayout(device(), otherSet, 0), std::logic_error);
  ShaderInterface runtimeArray = otherSet;
  runtimeArray.bindings[0].set = 0;
  runtimeArray.bindings[0].count = 0;
  EXPECT_THROW(PipelineLayout(device(), runtimeArray, 0), std::logic_error);

  const PipelineLayout layout(device(), reflected("slopes.comp"), 0);
  EXPECT_EQ(layout.descriptorType(1), VK_DESCRIPTOR_TYPE_STORAGE_IMAGE);
  EXPECT_THROW(layout.descriptorType(2), std::logic_error);
  const Buffer buffer(device(), 16, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, MemoryIntent::Upload);
  // (Each throws before recording anything, so no command buffer is needed.)
  EXPECT_THROW(DescriptorWrites().buffer(1, buffer).push(VK_NULL_HANDLE,
                                                         VK_PIPELINE_BIND_POINT_COMPUTE, layout),
               std::logic_error);
  EXPECT_THROW(DescriptorWrites()
                   .image(0, VK_NULL_HANDLE)
                   .push(VK_NULL_HANDLE, VK_PIPELINE_BIND_POINT_COMPUTE, layout),
               std::logic_error);
}

}  // namespace
}  // namespace aal
