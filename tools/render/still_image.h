// aal-render -o: the frame at the output's size, and the one image of a run
// without a sequence, with its --stats.
#pragma once

#include <cstdint>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/tools/render/render_options.h"

namespace aal {

// A frame of -o at the output's size: with --supersample N rendered at N
// times the width and height (the renderer's size) and averaged down
// (engine/supersampling.h); an explicit --lod-error stays in output pixels.
// Each frame of a sequence is one too (`accumulate`: of a --temporal
// sequence, engine/supersampling.h).
FrameResult renderOutputFrame(const RenderOptions& o, const TerrainScene& scene,
                              TerrainRenderer& renderer, const FrameSettings& settings,
                              bool accumulate = false);

// Renders and writes -o, then prints --stats (the device, the frame's
// triangles, textures and pass times, the sun of `sun`). Returns the exit
// code.
int renderStillImage(const RenderOptions& o, const Device& device, const TerrainScene& scene,
                     TerrainRenderer& renderer, const FrameSettings& settings, uint32_t width,
                     uint32_t height, const SolarPosition& sun);

}  // namespace aal
