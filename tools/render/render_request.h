// What an aal-render run is asked to do, its options checked against each
// other and its paths against each other before any file is read: the
// errors a user can act on come first, in the order they are reported.
#pragma once

#include <cstdint>
#include <optional>

#include <glm/vec3.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/tools/render/image_sequence.h"
#include "aperture/tools/render/render_options.h"

namespace aal {

struct RenderRequest {
  bool reference = false;  // --mode reference: the CPU ray tracer
  ShadingMode mode = ShadingMode::Approx;
  uint32_t width = 0, height = 0;         // --size
  glm::vec3 baseAlbedo{0};                // --base-color
  std::optional<glm::vec3> albedoValue;   // --albedo-value
  std::optional<ImageSequence> sequence;  // with its camera path read
};

// The request of `o`; InputError for options that contradict each other,
// outputs that cannot be written and paths that meet (checkRenderPaths).
RenderRequest checkedRequest(const RenderOptions& o);

}  // namespace aal
