#include "aperture/tools/render/still_image.h"

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "aperture/engine/screenshot.h"
#include "aperture/engine/supersampling.h"
#include "aperture/engine/vk/serial_pass_timer.h"
#include "aperture/tools/median.h"
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

// --pass-profile N: the frame in one submission and with each step on its
// own (TerrainRenderer::profile), alternated N times; medians.
void printPassProfile(const TerrainScene& scene, TerrainRenderer& renderer,
                      const FrameSettings& settings, int frames, FILE* out) {
  std::vector<std::string> names;
  std::map<std::string, std::vector<double>> wall, cpu;
  std::vector<double> whole, wholeCpu;
  for (int i = 0; i < frames; ++i) {
    const SerialPassTimer::Step frame = renderer.profile(scene, settings, false).at(0);
    whole.push_back(frame.wallMs);
    wholeCpu.push_back(frame.cpuMs);
    for (const SerialPassTimer::Step& step : renderer.profile(scene, settings, true)) {
      if (!wall.count(step.name)) names.push_back(step.name);
      wall[step.name].push_back(step.wallMs);
      cpu[step.name].push_back(step.cpuMs);
    }
  }
  std::fprintf(out, "pass profile: medians of %d frames, each pass submitted on its own\n", frames);
  std::fprintf(out, "%-30s %9s %9s\n", "step", "wall ms", "cpu ms");
  double wallSum = 0, cpuSum = 0;
  for (const std::string& name : names) {
    const double w = median(wall[name]), c = median(cpu[name]);
    std::fprintf(out, "%-30s %9.2f %9.2f\n", name.c_str(), w, c);
    wallSum += w;
    cpuSum += c;
  }
  std::fprintf(out, "%-30s %9.2f %9.2f\n", "sum of the steps", wallSum, cpuSum);
  std::fprintf(out, "%-30s %9.2f %9.2f\n", "frame in one submission", median(whole),
               median(wholeCpu));
}

}  // namespace

FrameResult renderOutputFrame(const RenderOptions& o, const TerrainScene& scene,
                              TerrainRenderer& renderer, const FrameSettings& settings,
                              bool accumulate) {
  return renderSupersampled(renderer, scene, settings, o.supersample, wantsLinearOutput(o.output),
                            accumulate);
}

int renderStillImage(const RenderOptions& o, const Device& device, const TerrainScene& scene,
                     TerrainRenderer& renderer, const FrameSettings& settings, uint32_t width,
                     uint32_t height, const SolarPosition& sun) {
  const FrameResult frame = renderOutputFrame(o, scene, renderer, settings);
  writeFrame(o.output, frame);
  if (o.stats)
    printFrameStats(device, scene, frame, settings, width, height, sun,
                    textOutput(o.report.style()));
  if (o.passProfile > 0) {
    printPassProfile(scene, renderer, settings, o.passProfile, textOutput(o.report.style()));
  }
  if (!o.report.quiet) std::fprintf(stderr, "aal-render: wrote %s\n", o.output.c_str());
  return kExitOk;
}

}  // namespace aal
