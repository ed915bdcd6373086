// The compiled shaders, built into the library as SPIR-V words
// (cmake/EmbedShaders.cmake): an installed tool or a program linking
// aperture needs no shader files beside it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace aal {

struct EmbeddedShader {
  const char* name;       // the source's file name, e.g. "caps_parity.comp"
  const uint32_t* words;  // SPIR-V, starting with its magic number
  size_t wordCount;
};

// Every shader, sorted by name.
std::span<const EmbeddedShader> embeddedShaders();

}  // namespace aal
