#include "aperture/tools/options/gpu_options.h"

#include <string>

#include "aperture/tools/tool_main.h"

namespace aal {

void addGpuOptions(CLI::App& app, GpuOptions& gpu, bool panel) {
  app.add_option("--device", gpu.device, "Vulkan device index (default: the best one)")
      ->check(kNonNegative);
  app.add_option("--triangles", gpu.triangleBudget,
                 "per-frame triangle budget of the terrain's quadtree LOD")
      ->check(CLI::Range(size_t(2), size_t(1) << 28))
      ->capture_default_str();
  app.add_option("--lod-error", gpu.lodErrorPixels,
                 "largest geometric error of the terrain mesh in pixels: the quadtree LOD "
                 "refines where a coarser level's height error would cover more on screen "
                 "(smaller: more triangles; the shading's detail comes from textures). "
                 "Default: 4 at 720 lines, in proportion to the rendered height, at least 1")
      ->check(CLI::Range(1e-3, 1e3));
  const std::string anisotropy =
      "texture filtering along each pixel's footprint on the DEM: up to N trilinear probes along "
      "its longer axis (1: one trilinear fetch, a GPU's isotropic filter, blurred in oblique "
      "views; each probe more costs a fetch per texture, about +12 % of a CPU frame: "
      "docs/rendering.md, \"Footprint filtering\")";
  app.add_option("--anisotropy", gpu.anisotropy,
                 panel ? anisotropy + "; the panel changes it" : anisotropy)
      ->check(CLI::Range(1, kMaxFootprintProbes))
      ->capture_default_str();
}

}  // namespace aal
