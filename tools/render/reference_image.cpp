#include "aperture/tools/render/reference_image.h"

#include <chrono>
#include <cstdio>

#include "aperture/engine/screenshot.h"
#include "aperture/preprocess/progress_reporter.h"
#include "aperture/terrain/reference/reference_renderer.h"
#include "aperture/tools/mode_comparison.h"
#include "aperture/tools/render/comparison_run.h"
#include "aperture/tools/tool_main.h"

namespace aal {

int renderReferenceImage(const RenderOptions& o, const Heightfield& field,
                         const FrameSettings& settings, uint32_t width, uint32_t height,
                         const std::optional<glm::vec3>& albedoValue) {
  const ReferenceSettings r =
      referenceSettingsFor(settings, width, height, comparisonOptions(o, albedoValue));
  ProgressReporter bar(o.report.style(), "tracing", "ray tracing");
  const auto start = std::chrono::steady_clock::now();
  const ReferenceImage image = renderReference(field, r, [&](double f) { bar.update(f); });
  bar.finish();
  writeFrame(o.output, referenceFrame(image, settings.lighting.exposure));
  if (!o.report.quiet) {
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::fprintf(stderr,
                 "aal-render: reference (%d sun + %d sky rays per pixel over %d x %d "
                 "subpixels) in %.1f s, wrote %s\n",
                 r.sunRays, r.skyRays, r.subpixels, r.subpixels, seconds, o.output.c_str());
  }
  return kExitOk;
}

}  // namespace aal
