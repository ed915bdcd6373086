#include "aperture/tools/render/still_image.h"

#include <cstdio>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/supersampling.h"
#include "aperture/tools/tool_main.h"

namespace aal {
namespace {

// --stats on `out` (stdout, or stderr with --progress json).
void printFrameStats(const Device& device, const TerrainScene& scene, const FrameResult& frame,
                     const FrameSettings& settings, uint32_t width, uint32_t height,
                     const SolarPosition& sun, FILE* out) {
  std::fprintf(out, "device     %s\n", device.name().c_str());
  std::fprintf(out, "size       %ux%u\n", width, height);
  std::fprintf(out, "triangles  %zu\n", frame.triangles);
  std::fprintf(out, "textures   %s, %.1f MiB\n", describeTerrainTiles(scene.tiles()).c_str(),
               double(scene.textureBytes()) / (1 << 20));
  if (scene.hasHorizons()) {
    std::fprintf(out, "horizons   %.1f MiB of them (moments of two directions)\n",
                 double(scene.horizonBytes()) / (1 << 20));
  }
  std::fprintf(out, "sun        azimuth %.2f deg, elevation %.2f deg\n", sun.azimuthDeg,
               sun.elevationDeg);
  const ObscuranceSettings& obscurance = settings.obscurance;
  if (obscurance.enabled) {
    std::fprintf(out, "obscurance R %.1f m, n %d, m %d\n", obscurance.radiusM, obscurance.samples,
                 obscurance.steps);
  } else {
    std::fprintf(out, "obscurance off\n");
  }
  double total = 0;
  for (const auto& [pass, ms] : frame.passMilliseconds) {
    std::fprintf(out, "gpu %-10s %8.3f ms\n", pass.c_str(), ms);
    total += ms;
  }
  std::fprintf(out, "gpu total      %8.3f ms\n", total);
}

}  // namespace

FrameResult renderOutputFrame(const RenderOptions& o, const TerrainScene& scene,
                              TerrainRenderer& renderer, const FrameSettings& settings) {
  return renderSupersampled(renderer, scene, settings, o.supersample, wantsLinearOutput(o.output));
}

int renderStillImage(const RenderOptions& o, const Device& device, const TerrainScene& scene,
                     TerrainRenderer& renderer, const FrameSettings& settings, uint32_t width,
                     uint32_t height, const SolarPosition& sun) {
  const FrameResult frame = renderOutputFrame(o, scene, renderer, settings);
  writeFrame(o.output, frame);
  if (o.stats)
    printFrameStats(device, scene, frame, settings, width, height, sun,
                    textOutput(o.report.style()));
  if (!o.report.quiet) std::fprintf(stderr, "aal-render: wrote %s\n", o.output.c_str());
  return kExitOk;
}

}  // namespace aal
