// aal-render --mode reference: the image of the CPU ray tracer alone, no
// Vulkan device needed (docs/comparison.md).
#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/tools/render/render_options.h"

namespace aal {

// Ray traces `settings` at width x height into -o; `albedoValue` is the
// terrain's constant albedo (the reference's default when none). Returns
// the exit code.
int renderReferenceImage(const RenderOptions& o, const Heightfield& field,
                         const FrameSettings& settings, uint32_t width, uint32_t height,
                         const std::optional<glm::vec3>& albedoValue);

}  // namespace aal
