// The descriptor bindings a SPIR-V module declares, read from its words, so
// that pipeline layouts follow the shaders instead of restating them
// (docs/design.md §8).
#pragma once

#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include <vulkan/vulkan.h>

namespace aal {

// A module that is not well-formed SPIR-V (too short, wrong magic, an
// instruction running past the end), or declares a resource Vulkan cannot
// bind. The message says which and where.
class SpirvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One descriptor a shader declares: a declaration counts whether or not the
// code reads it (a layout must cover what every variant of a pipeline might
// be given).
struct DescriptorBinding {
  uint32_t set = 0;
  uint32_t binding = 0;
  VkDescriptorType type = VK_DESCRIPTOR_TYPE_MAX_ENUM;
  // Elements of an arrayed resource: 1 when not arrayed, 0 when runtime-sized.
  uint32_t count = 1;
  VkShaderStageFlags stages = 0;

  bool operator==(const DescriptorBinding&) const = default;
};

// What a module (or the modules of one pipeline, merged) needs of a layout.
struct ShaderInterface {
  VkShaderStageFlags stages = 0;  // of the entry points
  // Sorted by set, then binding; one entry per (set, binding).
  std::vector<DescriptorBinding> bindings;
};

// Reads the entry points' stages and the variables of storage class
// UniformConstant, Uniform and StorageBuffer with their DescriptorSet and
// Binding decorations, following pointers and arrays to the resource type
// (the Vulkan specification's "Shader Resource and Descriptor Type
// Correspondence"). Either byte order. Throws SpirvError.
ShaderInterface reflectShaderInterface(std::span<const uint32_t> words);

// The interface of a pipeline made of `modules`: stages merged, one binding
// per (set, binding) visible to every stage that declares it. Throws
// SpirvError when two modules declare one binding with different types or
// counts.
ShaderInterface mergeShaderInterfaces(const std::vector<ShaderInterface>& modules);

}  // namespace aal
