// Bakes a synthetic DEM and renders one frame headless through the installed
// library, with the Vulkan validation layer on. Exits 0 when the frame shows
// lit terrain under a sky and the layer said nothing; prints why otherwise.
#include <aperture/engine/terrain_renderer.h>
#include <aperture/engine/terrain_scene.h>
#include <aperture/engine/vk/device.h>
#include <aperture/engine/vk/instance.h>
#include <aperture/preprocess/bake.h>
#include <aperture/terrain/light/sky_lighting.h>
#include <aperture/terrain/synthetic.h>
#include <aperture/terrain/version.h>

#include <cstdio>
#include <exception>
#include <set>

int main() {
  try {
    aal::SyntheticTerrainOptions terrain;
    terrain.width = terrain.height = 64;
    terrain.cellSizeM = 30;
    terrain.featureSizeTexels = 16;
    terrain.amplitudeM = 300;
    const aal::Heightfield field = aal::makeSyntheticTerrain(terrain);
    aal::BakeOptions bake;
    bake.azimuths = 16;
    const aal::ApertureMap aperture = aal::bakeApertures(field, bake).aperture;

    aal::InstanceOptions options;
    options.validation = true;
    aal::Instance instance(options);
    size_t messages = 0;
    size_t colours = 0;
    {
      aal::Device device(instance);
      const aal::TerrainScene scene(device, field, aperture, nullptr, 100000);
      aal::TerrainRenderer renderer(device, 128, 72);
      aal::FrameSettings frame;
      frame.mode = aal::ShadingMode::Approx;
      frame.camera.position = {-1200, -1200, 800};
      frame.camera.lookAt = {0, 0, 100};
      frame.camera.verticalFovDeg = 50;
      aal::setSunAndSky(frame.lighting, 135, 30, 2.5);
      const aal::FrameResult result = renderer.render(scene, frame, false);
      std::set<uint32_t> seen;
      for (size_t i = 0; i + 3 < result.display.size(); i += 4) {
        seen.insert(result.display[i] | result.display[i + 1] << 8 | result.display[i + 2] << 16);
      }
      colours = seen.size();
    }
    messages = instance.validationLog().count();
    for (const std::string& message : instance.validationLog().messages()) {
      std::fprintf(stderr, "validation: %s\n", message.c_str());
    }
    std::printf("%s: baked %dx%d, rendered 128x72 with %zu colours, %zu validation messages\n",
                aal::softwareName().c_str(), field.width, field.height, colours, messages);
    return messages == 0 && colours > 50 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aperture_consumer: %s\n", e.what());
    return 1;
  }
}
