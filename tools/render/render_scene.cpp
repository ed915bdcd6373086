#include "aperture/tools/render/render_scene.h"

#include <stdexcept>
#include <utility>

#include "aperture/engine/terrain_tiles.h"
#include "aperture/preprocess/aperture_cache.h"
#include "aperture/terrain/errors.h"
#include "aperture/tools/horizon_option.h"

namespace aal {

ApertureSource apertureSource(const RenderOptions& o, const Heightfield& field, bool reference) {
  ApertureSource source{o.aperture, {}};
  if (reference) {
    // The ray tracer needs no aperture map.
  } else if (!source.path.empty()) {
    const ApertureMapReader check(source.path);
    checkApertureMatchesDem(check.header(), source.path, field, o.dem);
  } else {
    std::vector<std::string> inputs = {o.albedo, o.cameraPath};
    inputs.insert(inputs.end(), o.horizons.begin(), o.horizons.end());
    CachedAperture cached = cachedOrBakedAperture(field, o.dem, BakeOptions{}, o.report.style(),
                                                  o.report.quiet, inputs);
    source.path = cached.path.string();
    source.inMemory = std::move(cached.map);
  }
  return source;
}

void checkDeviceLimits(const RenderOptions& o, const Device& device, uint32_t width,
                       uint32_t height, const Heightfield& field) {
  const uint32_t largest = device.properties().limits.maxImageDimension2D;
  if (width > largest || height > largest) {
    throw InputError("--size " + o.size + " exceeds the device's largest image (" +
                     std::to_string(largest) + ")");
  }
  if (uint64_t(width) * o.supersample > largest || uint64_t(height) * o.supersample > largest) {
    throw InputError("--size " + o.size + " with --supersample " + std::to_string(o.supersample) +
                     " renders " + std::to_string(uint64_t(width) * o.supersample) + "x" +
                     std::to_string(uint64_t(height) * o.supersample) +
                     ", beyond the device's largest image (" + std::to_string(largest) +
                     "): a smaller --size or --supersample");
  }
  if (o.maxTileTexels > 0) {
    // A forced tile size that needs more texture pages than the renderer
    // binds is a bad argument, not a failure of the run.
    try {
      planTerrainTiles(static_cast<uint32_t>(field.width), static_cast<uint32_t>(field.height),
                       deviceTileLimits(device, TerrainTiling{o.maxTileTexels, 0}));
    } catch (const std::runtime_error& e) {
      throw InputError("--max-tile " + std::to_string(o.maxTileTexels) + ": " + e.what());
    }
  }
}

std::unique_ptr<TerrainScene> buildScene(const RenderOptions& o, const Device& device,
                                         const Heightfield& field, ApertureSource aperture,
                                         std::optional<AlbedoImage> albedo) {
  const AlbedoImage* albedoImage = albedo ? &*albedo : nullptr;
  const TerrainTiling tiling{o.maxTileTexels, 0};
  if (aperture.path.empty()) {
    return std::make_unique<TerrainScene>(device, field, aperture.inMemory, albedoImage,
                                          o.gpu.triangleBudget, tiling);
  }
  ApertureMapReader reader(aperture.path);
  return std::make_unique<TerrainScene>(device, field, reader, albedoImage, o.gpu.triangleBudget,
                                        tiling);
}

std::vector<std::shared_ptr<const HorizonMap>> loadHorizonMaps(
    const RenderOptions& o, const std::optional<ImageSequence>& sequence, const Heightfield& field,
    const FrameSettings& settings, const Device& device, TerrainScene& scene) {
  FrameSettings first = settings;
  if (sequence) setSequenceFrame(o, *sequence, field, 0, first);
  const float firstAzimuth = sunAzimuthRad(first.lighting.sunDirection);
  std::vector<std::shared_ptr<const HorizonMap>> horizonMaps;
  for (const std::string& path : o.horizons) {
    auto horizons = std::make_shared<const HorizonMap>(readHorizonsOfDem(path, field));
    try {
      scene.setHorizons(device, horizons, horizonPairFor(horizons->directions, firstAzimuth, -1));
    } catch (const std::invalid_argument& e) {
      throw InputError(std::string("--horizons: ") + e.what());
    }
    horizonMaps.push_back(std::move(horizons));
  }
  return horizonMaps;
}

}  // namespace aal
