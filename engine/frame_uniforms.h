// C++ twin of the Frame uniform block of shaders/frame.glsl (std140).
#pragma once

#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "sky_model.h"

namespace aal {

struct FrameUniforms {
  glm::mat4 viewProj{1.0f};
  glm::mat4 invViewProj{1.0f};
  glm::vec4 cameraPos{0.0f};
  glm::vec4 sunDirection{0.0f};   // xyz, w: sun angular radius (rad)
  glm::vec4 sunIrradiance{0.0f};  // rgb
  glm::vec4 skyRadiance{0.0f};    // rgb, w: haze density (1/m)
  glm::vec4 dem{0.0f};            // width, height, cell x, cell y
  glm::vec4 heights{0.0f};        // min, max, water level, water on
  glm::ivec4 grid{0};             // LOD patch quads, LOD levels, mode, albedo source (AAL_ALBEDO_*)
  glm::vec4 display{0.0f};        // exposure, raw output, background alpha
  glm::vec4 albedoValue{0.0f};    // rgb constant albedo
  glm::vec4 obscurance{0.0f};     // R (m), n, m
  glm::ivec4 obscurancePass{0};   // on, interleaved + filtered, pixel size (1 or 2)
  glm::ivec4 tileGrid{0};         // tile core width, height, tiles across, down
  glm::ivec4 tileImage{0};        // tile border, 0, tile image width, height
  glm::ivec4 tileLayers{0};       // layers per page: heights, apertures, albedo, 0
  glm::ivec4 extent{0};           // pixels drawn this frame: width, height, 0, 0
  glm::mat4 previousViewProj{1.0f};  // the previous frame's (obscurance reuse)
  glm::ivec4 history{-1, 0, 0, 0};   // subset (-1: all), history valid, previous extent
  glm::vec4 pixelAngle{0.0f};        // x: 2 tan(fov / 2) / extent height
  glm::vec4 base{0.0f};              // solid base: rgb albedo, w: bottom height (m)
  PreethamSky sky;
};
static_assert(sizeof(FrameUniforms) == 3 * 64 + 18 * 16 + sizeof(PreethamSky),
              "FrameUniforms must match the std140 Frame block of shaders/frame.glsl");

}  // namespace aal
