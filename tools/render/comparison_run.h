// aal-render --compare FOLDER: every GPU shading mode against the CPU
// reference, the files of tools/mode_comparison.h and a table on stdout
// (docs/comparison.md).
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/tools/mode_comparison.h"
#include "aperture/tools/render/image_sequence.h"
#include "aperture/tools/render/render_options.h"

namespace aal {

// The reference's rays and samples from the options; its constant albedo
// `albedoValue`, else the reference's default.
ComparisonOptions comparisonOptions(const RenderOptions& o,
                                    const std::optional<glm::vec3>& albedoValue);

// The modes --compare renders, by name: comparisonFileNames gives its files.
std::vector<std::string> comparedModeNames(const RenderOptions& o);

// --compare FOLDER: every mode against the reference, a table on stdout.
// With several horizon maps, one horizon mode for each ("horizon-STEM"), the
// scene given each map before its rendering: one reference for all. With a
// camera path, the still images are its first frame's, and every mode and
// the reference are rendered along it for their shimmer. Returns the exit
// code.
int runComparison(const RenderOptions& o, const Heightfield& field, TerrainScene& scene,
                  TerrainRenderer& renderer, FrameSettings settings,
                  const std::optional<glm::vec3>& albedoValue, const Device& device,
                  const std::vector<std::shared_ptr<const HorizonMap>>& horizons,
                  const std::optional<ImageSequence>& pan);

}  // namespace aal
