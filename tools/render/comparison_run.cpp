#include "aperture/tools/render/comparison_run.h"

#include <cstdio>
#include <filesystem>

#include "aperture/preprocess/progress_reporter.h"
#include "aperture/terrain/light/tone_map.h"
#include "aperture/terrain/reference/reference_renderer.h"
#include "aperture/tools/tool_main.h"

namespace aal {
namespace {

// The horizon modes --compare adds, one per --horizons file: "horizon", or
// with several "horizon-STEM" (numbered when a name is taken, so that no
// output is lost).
std::vector<std::string> horizonModeNames(const std::vector<std::string>& horizonPaths,
                                          const std::vector<ComparedMode>& defaultModes) {
  std::vector<std::string> taken, names;
  for (const ComparedMode& m : defaultModes) taken.push_back(m.name);
  for (size_t i = 0; i < horizonPaths.size(); ++i) {
    std::string name = horizonPaths.size() == 1
                           ? std::string("horizon")
                           : "horizon-" + std::filesystem::path(horizonPaths[i]).stem().string();
    for (const std::string& other : taken) {
      if (other == name) name.append("-").append(std::to_string(i + 1));
    }
    taken.push_back(name);
    names.push_back(name);
  }
  return names;
}

// The default modes and one horizon mode per map; with several maps each
// mode gives the scene its map first.
std::vector<ComparedMode> comparedModes(
    const RenderOptions& o, TerrainScene& scene, const FrameSettings& settings,
    const Device& device, const std::vector<std::shared_ptr<const HorizonMap>>& horizons) {
  std::vector<ComparedMode> modes = defaultComparedModes(settings);
  const std::vector<std::string> names = horizonModeNames(o.horizons, modes);
  for (size_t i = 0; i < horizons.size(); ++i) {
    ComparedMode m{names[i], ShadingMode::Horizon, settings.obscurance.enabled};
    if (horizons.size() > 1) {
      // Laid for the one sun (horizonPairFor): no re-lay in the frame.
      const int first = horizonPairFor(horizons[i]->directions,
                                       sunAzimuthRad(settings.lighting.sunDirection), -1);
      m.prepare = [&scene, &device, &horizons, i, first] {
        scene.setHorizons(device, horizons[i], first);
      };
    }
    modes.push_back(std::move(m));
  }
  return modes;
}

// The table of --compare on `out` (stdout, or stderr with --progress json): each mode's errors and,
// along a pan, its shimmer (kcd/m²) and the ratio to the reference's (whose row comes last).
void printComparison(const Comparison& c, FILE* out) {
  const bool pan = c.referenceShimmer.has_value();
  std::fprintf(out, "%-20s %14s %22s", "mode", "relative RMSE", "mean relative error");
  if (pan) std::fprintf(out, " %12s %12s", "shimmer", "x reference");
  std::fprintf(out, "\n");
  const auto shimmer = [&](double s) {
    std::fprintf(out, " %12.5f %12.2f", s, *c.referenceShimmer > 0 ? s / *c.referenceShimmer : 0.0);
  };
  for (const ModeError& e : c.modes) {
    std::fprintf(out, "%-20s %13.2f%% %21.2f%%", e.mode.c_str(), 100 * e.relativeRmse,
                 100 * e.meanRelativeError);
    if (pan) shimmer(e.shimmer.value_or(0));
    std::fprintf(out, "\n");
  }
  if (pan) {
    std::fprintf(out, "%-20s %14s %22s", "reference", "", "");
    shimmer(*c.referenceShimmer);
    std::fprintf(out, "\n");
  }
}

}  // namespace

ComparisonOptions comparisonOptions(const RenderOptions& o,
                                    const std::optional<glm::vec3>& albedoValue) {
  ComparisonOptions c;
  c.sunRays = o.referenceSunRays;
  c.skyRays = o.referenceSkyRays;
  c.subpixels = o.referenceSubpixels;
  c.albedo = albedoValue.value_or(glm::vec3(kReferenceTerrainAlbedo));
  c.supersample = o.supersample;
  // Along the pan, as a --camera-path sequence draws its frames.
  c.temporal = o.temporal != "off";
  return c;
}

std::vector<std::string> comparedModeNames(const RenderOptions& o) {
  FrameSettings settings;
  settings.obscurance.enabled = !o.noObscurance;
  std::vector<std::string> names;
  const std::vector<ComparedMode> modes = defaultComparedModes(settings);
  for (const ComparedMode& m : modes) names.push_back(m.name);
  for (const std::string& name : horizonModeNames(o.horizons, modes)) names.push_back(name);
  return names;
}

int runComparison(const RenderOptions& o, const Heightfield& field, TerrainScene& scene,
                  TerrainRenderer& renderer, FrameSettings settings,
                  const std::optional<glm::vec3>& albedoValue, const Device& device,
                  const std::vector<std::shared_ptr<const HorizonMap>>& horizons,
                  const std::optional<ImageSequence>& pan) {
  std::vector<Camera> cameras;
  if (pan && pan->path) {
    for (int i = 0; i < pan->frames; ++i) {
      cameras.push_back(pan->path->at(pan->path->frameTime(i, pan->frames)));
    }
    settings.camera = cameras.front();
  }
  ProgressReporter bar(o.report.style(), "tracing", "ray tracing the reference");
  const std::vector<ComparedMode> modes = comparedModes(o, scene, settings, device, horizons);
  Comparison c = compareModes(renderer, scene, field, settings, modes,
                              comparisonOptions(o, albedoValue), [&](double f) { bar.update(f); });
  bar.finish();
  if (!cameras.empty()) {
    ProgressReporter panBar(o.report.style(), "rendering",
                            "rendering the pan (" + std::to_string(cameras.size()) + " frames)");
    measureShimmer(c, renderer, scene, field, settings, modes, comparisonOptions(o, albedoValue),
                   cameras, [&](double f) { panBar.update(f); });
    panBar.finish();
  }
  writeComparison(o.compare, c, settings.lighting.exposure);
  printComparison(c, textOutput(o.report.style()));
  if (!o.report.quiet) {
    std::fprintf(stderr, "aal-render: reference in %.1f s; wrote %s/\n", c.referenceSeconds,
                 o.compare.c_str());
  }
  return kExitOk;
}

}  // namespace aal
