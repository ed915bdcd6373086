// aal-render's GPU side: the aperture map the scene is built from, the
// device's limits against the options, the scene and its horizon maps.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/engine/vk/device.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/albedo_image.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/tools/render/image_sequence.h"
#include "aperture/tools/render/render_options.h"

namespace aal {

// The aperture map is streamed from its file into the GPU when the scene
// is built, so it never sits in host memory as floats: a path (--aperture,
// or the cache's), or a fresh bake's map in memory when the cache keeps
// none.
struct ApertureSource {
  std::string path;
  ApertureMap inMemory;
};

// --aperture checked against the DEM, else the cached or baked map; none
// for the ray tracer (`reference`).
ApertureSource apertureSource(const RenderOptions& o, const Heightfield& field, bool reference);

// InputError when the image at --size (times --supersample) exceeds the
// device's largest, or when --max-tile needs more texture pages than the
// renderer binds.
void checkDeviceLimits(const RenderOptions& o, const Device& device, uint32_t width,
                       uint32_t height, const Heightfield& field);

// The scene of the DEM, its aperture map and albedo image (consumed: their
// host memory is freed once they are on the device).
std::unique_ptr<TerrainScene> buildScene(const RenderOptions& o, const Device& device,
                                         const Heightfield& field, ApertureSource aperture,
                                         std::optional<AlbedoImage> albedo);

// Each --horizons map, read and checked against the DEM, given to the scene
// in turn (the last stays). The horizons of the two directions beside the
// first frame's sun are laid on the device (horizonPairFor): no re-lay
// before it. A sequence's later suns re-lay when they leave that pair.
std::vector<std::shared_ptr<const HorizonMap>> loadHorizonMaps(
    const RenderOptions& o, const std::optional<ImageSequence>& sequence, const Heightfield& field,
    const FrameSettings& settings, const Device& device, TerrainScene& scene);

}  // namespace aal
