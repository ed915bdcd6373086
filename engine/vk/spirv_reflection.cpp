#include "aperture/engine/vk/spirv_reflection.h"

#include <algorithm>
#include <optional>
#include <string>
#include <unordered_map>

namespace aal {

namespace {

// Numbers from the SPIR-V specification (Khronos, version 1.6), §2.3
// (physical layout) and §3 (binary form).
constexpr uint32_t kMagic = 0x07230203;
constexpr size_t kHeaderWords = 5;  // magic, version, generator, id bound, schema

enum Opcode : uint32_t {
  kOpEntryPoint = 15,
  kOpTypeImage = 25,
  kOpTypeSampler = 26,
  kOpTypeSampledImage = 27,
  kOpTypeArray = 28,
  kOpTypeRuntimeArray = 29,
  kOpTypeStruct = 30,
  kOpTypePointer = 32,
  kOpConstant = 43,
  kOpSpecConstant = 50,
  kOpVariable = 59,
  kOpDecorate = 71,
  kOpTypeAccelerationStructureKHR = 5341,
};

enum Decoration : uint32_t {
  kBlock = 2,
  kBufferBlock = 3,
  kBinding = 33,
  kDescriptorSet = 34,
};

enum StorageClass : uint32_t {
  kUniformConstant = 0,
  kUniform = 2,
  kStorageBuffer = 12,
};

enum ImageDim : uint32_t { kDimBuffer = 5, kDimSubpassData = 6 };

std::optional<VkShaderStageFlagBits> stageOf(uint32_t executionModel) {
  switch (executionModel) {
    case 0: return VK_SHADER_STAGE_VERTEX_BIT;
    case 1: return VK_SHADER_STAGE_TESSELLATION_CONTROL_BIT;
    case 2: return VK_SHADER_STAGE_TESSELLATION_EVALUATION_BIT;
    case 3: return VK_SHADER_STAGE_GEOMETRY_BIT;
    case 4: return VK_SHADER_STAGE_FRAGMENT_BIT;
    case 5: return VK_SHADER_STAGE_COMPUTE_BIT;
    case 5313: return VK_SHADER_STAGE_RAYGEN_BIT_KHR;
    case 5314: return VK_SHADER_STAGE_INTERSECTION_BIT_KHR;
    case 5315: return VK_SHADER_STAGE_ANY_HIT_BIT_KHR;
    case 5316: return VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR;
    case 5317: return VK_SHADER_STAGE_MISS_BIT_KHR;
    case 5318: return VK_SHADER_STAGE_CALLABLE_BIT_KHR;
    case 5364: return VK_SHADER_STAGE_TASK_BIT_EXT;
    case 5365: return VK_SHADER_STAGE_MESH_BIT_EXT;
    default: return std::nullopt;
  }
}

struct Decorations {
  std::optional<uint32_t> set, binding;
  bool block = false, bufferBlock = false;
};

struct Variable {
  uint32_t id, pointerType, storageClass;
};

// Adds `b` to the sorted `list`, merging its stages into an equal binding.
void addBinding(std::vector<DescriptorBinding>& list, const DescriptorBinding& b) {
  const auto before = [](const DescriptorBinding& x, const DescriptorBinding& y) {
    return x.set != y.set ? x.set < y.set : x.binding < y.binding;
  };
  const auto at = std::lower_bound(list.begin(), list.end(), b, before);
  if (at == list.end() || before(b, *at)) {
    list.insert(at, b);
    return;
  }
  if (at->type != b.type || at->count != b.count) {
    throw SpirvError("set " + std::to_string(b.set) + " binding " + std::to_string(b.binding) +
                     " is declared with two different descriptor types or array sizes");
  }
  at->stages |= b.stages;
}

// One pass over the instructions, keeping what resolving the resource
// variables needs: where each type or constant is defined, the decorations.
class Module {
 public:
  explicit Module(std::span<const uint32_t> words) : words_(words) {
    if (words_.size() < kHeaderWords) {
      throw SpirvError("SPIR-V module truncated: " + std::to_string(words_.size()) +
                       " words, the header alone has 5");
    }
    bound_ = words_[3];
    for (size_t at = kHeaderWords; at < words_.size();) {
      const uint32_t wordCount = words_[at] >> 16, opcode = words_[at] & 0xffffu;
      if (wordCount == 0) {
        throw SpirvError("SPIR-V instruction at word " + std::to_string(at) + " has word count 0");
      }
      if (wordCount > words_.size() - at) {
        throw SpirvError("SPIR-V module truncated: the instruction at word " + std::to_string(at) +
                         " runs past the end");
      }
      read(at, opcode, wordCount);
      at += wordCount;
    }
    if (stages_ == 0) throw SpirvError("SPIR-V module has no entry point");
  }

  ShaderInterface shaderInterface() const {
    ShaderInterface result;
    result.stages = stages_;
    for (const Variable& v : variables_) {
      const Decorations d = decorationsOf(v.id);
      if (!d.set || !d.binding) {
        throw SpirvError("SPIR-V resource %" + std::to_string(v.id) +
                         " lacks a DescriptorSet or Binding decoration");
      }
      const auto [type, count] = resourceOf(v);
      addBinding(
          result.bindings,
          {.set = *d.set, .binding = *d.binding, .type = type, .count = count, .stages = stages_});
    }
    return result;
  }

 private:
  // Needs `words` operands after the opcode word of the instruction at `at`.
  void need(size_t at, uint32_t wordCount, uint32_t words) const {
    if (wordCount < 1 + words) {
      throw SpirvError("SPIR-V instruction at word " + std::to_string(at) + " is too short");
    }
  }

  uint32_t id(uint32_t value, size_t at) const {
    if (value == 0 || value >= bound_) {
      throw SpirvError("SPIR-V id " + std::to_string(value) + " at word " + std::to_string(at) +
                       " is outside the module's bound");
    }
    return value;
  }

  void read(size_t at, uint32_t opcode, uint32_t wordCount) {
    switch (opcode) {
      case kOpEntryPoint: {
        need(at, wordCount, 3);
        const auto stage = stageOf(words_[at + 1]);
        if (!stage) {
          throw SpirvError("SPIR-V entry point of execution model " +
                           std::to_string(words_[at + 1]) + " is not a Vulkan shader stage");
        }
        stages_ |= *stage;
        break;
      }
      case kOpDecorate: {
        need(at, wordCount, 2);
        Decorations& d = decorations_[id(words_[at + 1], at)];
        switch (words_[at + 2]) {
          case kBlock: d.block = true; break;
          case kBufferBlock: d.bufferBlock = true; break;
          case kBinding:
            need(at, wordCount, 3);
            d.binding = words_[at + 3];
            break;
          case kDescriptorSet:
            need(at, wordCount, 3);
            d.set = words_[at + 3];
            break;
          default: break;
        }
        break;
      }
      case kOpVariable: {
        need(at, wordCount, 3);
        const uint32_t storage = words_[at + 3];
        if (storage == kUniformConstant || storage == kUniform || storage == kStorageBuffer) {
          variables_.push_back({id(words_[at + 2], at), id(words_[at + 1], at), storage});
        }
        break;
      }
      case kOpTypeImage:
      case kOpTypeSampler:
      case kOpTypeSampledImage:
      case kOpTypeArray:
      case kOpTypeRuntimeArray:
      case kOpTypeStruct:
      case kOpTypePointer:
      case kOpTypeAccelerationStructureKHR:
        need(at, wordCount, 1);
        definitions_[id(words_[at + 1], at)] = {at, wordCount};
        break;
      case kOpConstant:
      case kOpSpecConstant:  // an array sized by one: its default value
        need(at, wordCount, 3);
        definitions_[id(words_[at + 2], at)] = {at, wordCount};
        break;
      default: break;
    }
  }

  Decorations decorationsOf(uint32_t target) const {
    const auto it = decorations_.find(target);
    return it == decorations_.end() ? Decorations{} : it->second;
  }

  struct Definition {
    size_t at;
    uint32_t wordCount;
    uint32_t opcode(std::span<const uint32_t> words) const { return words[at] & 0xffffu; }
  };

  // The instruction defining `target`, which must be a type or constant the
  // reflection knows.
  Definition definitionOf(uint32_t target) const {
    const auto it = definitions_.find(target);
    if (it == definitions_.end()) {
      throw SpirvError("SPIR-V id %" + std::to_string(target) +
                       " is used as a resource type but not defined as one");
    }
    return it->second;
  }

  // Operand `i` (1 = the word after the opcode) of `def`.
  uint32_t operand(const Definition& def, uint32_t i) const {
    if (i >= def.wordCount) {
      throw SpirvError("SPIR-V instruction at word " + std::to_string(def.at) + " is too short");
    }
    return words_[def.at + i];
  }

  uint32_t arrayLength(uint32_t lengthId) const {
    const Definition def = definitionOf(lengthId);
    const uint32_t op = def.opcode(words_);
    if (op != kOpConstant && op != kOpSpecConstant) {
      throw SpirvError("SPIR-V array length %" + std::to_string(lengthId) + " is not a constant");
    }
    // A 64-bit length has its high word second; lengths never need it.
    if (def.wordCount > 4 && operand(def, 4) != 0) {
      throw SpirvError("SPIR-V array length %" + std::to_string(lengthId) + " is too large");
    }
    return operand(def, 3);
  }

  // The descriptor type and array count of a resource variable.
  std::pair<VkDescriptorType, uint32_t> resourceOf(const Variable& v) const {
    const Definition pointer = definitionOf(v.pointerType);
    if (pointer.opcode(words_) != kOpTypePointer) {
      throw SpirvError("SPIR-V variable %" + std::to_string(v.id) + " is not of a pointer type");
    }
    uint64_t count = 1;
    uint32_t typeId = operand(pointer, 3);
    Definition type = definitionOf(typeId);
    // Arrays (of arrays) of resources; a well-formed module defines a type
    // before its uses, so a malformed one could loop: cap the depth.
    for (int depth = 0;; ++depth) {
      const uint32_t op = type.opcode(words_);
      if (op != kOpTypeArray && op != kOpTypeRuntimeArray) break;
      if (depth == 32) throw SpirvError("SPIR-V array type nests too deep");
      count = op == kOpTypeRuntimeArray ? 0 : count * arrayLength(operand(type, 3));
      if (count > UINT32_MAX) throw SpirvError("SPIR-V resource array is too large");
      typeId = operand(type, 2);
      type = definitionOf(typeId);
    }
    return {descriptorTypeOf(v, typeId, type), static_cast<uint32_t>(count)};
  }

  VkDescriptorType imageDescriptorType(const Definition& image) const {
    const uint32_t dim = operand(image, 3), sampled = operand(image, 7);
    if (dim == kDimSubpassData) return VK_DESCRIPTOR_TYPE_INPUT_ATTACHMENT;
    if (sampled != 1 && sampled != 2) {
      throw SpirvError("SPIR-V image type at word " + std::to_string(image.at) +
                       " says neither sampled nor storage");
    }
    if (dim == kDimBuffer) {
      return sampled == 1 ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
                          : VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
    }
    return sampled == 1 ? VK_DESCRIPTOR_TYPE_SAMPLED_IMAGE : VK_DESCRIPTOR_TYPE_STORAGE_IMAGE;
  }

  VkDescriptorType descriptorTypeOf(const Variable& v, uint32_t typeId,
                                    const Definition& type) const {
    const uint32_t op = type.opcode(words_);
    if (v.storageClass == kUniformConstant) {
      switch (op) {
        case kOpTypeSampler: return VK_DESCRIPTOR_TYPE_SAMPLER;
        case kOpTypeImage: return imageDescriptorType(type);
        case kOpTypeSampledImage: {
          // A sampled buffer image (GLSL samplerBuffer) is a uniform texel buffer.
          const Definition image = definitionOf(operand(type, 2));
          if (image.opcode(words_) != kOpTypeImage) {
            throw SpirvError("SPIR-V sampled image type at word " + std::to_string(type.at) +
                             " is not of an image");
          }
          return operand(image, 3) == kDimBuffer ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
                                                 : VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER;
        }
        case kOpTypeAccelerationStructureKHR: return VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR;
        default: break;
      }
    } else if (op == kOpTypeStruct) {
      const Decorations d = decorationsOf(typeId);
      if (v.storageClass == kStorageBuffer && d.block) return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
      if (v.storageClass == kUniform && d.block) return VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER;
      if (v.storageClass == kUniform && d.bufferBlock) return VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    }
    throw SpirvError("SPIR-V resource %" + std::to_string(v.id) +
                     " is of no type a descriptor can hold");
  }

  std::span<const uint32_t> words_;
  uint32_t bound_ = 0;
  VkShaderStageFlags stages_ = 0;
  std::unordered_map<uint32_t, Definition> definitions_;
  std::unordered_map<uint32_t, Decorations> decorations_;
  std::vector<Variable> variables_;
};

uint32_t byteSwapped(uint32_t w) {
  return (w >> 24) | ((w >> 8) & 0xff00u) | ((w << 8) & 0xff0000u) | (w << 24);
}

}  // namespace

ShaderInterface reflectShaderInterface(std::span<const uint32_t> words) {
  if (words.empty()) throw SpirvError("SPIR-V module is empty");
  if (words[0] == kMagic) return Module(words).shaderInterface();
  if (words[0] == byteSwapped(kMagic)) {
    std::vector<uint32_t> swapped(words.size());
    std::transform(words.begin(), words.end(), swapped.begin(), byteSwapped);
    return Module(swapped).shaderInterface();
  }
  throw SpirvError("not a SPIR-V module: the first word is not the magic number 0x07230203");
}

ShaderInterface mergeShaderInterfaces(const std::vector<ShaderInterface>& modules) {
  ShaderInterface merged;
  for (const ShaderInterface& m : modules) {
    merged.stages |= m.stages;
    for (const DescriptorBinding& b : m.bindings) addBinding(merged.bindings, b);
  }
  return merged;
}

}  // namespace aal
