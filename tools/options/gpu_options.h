// How the GPU renderer draws the terrain, on the command line of aal-render
// and aal-view: --device, --triangles, --lod-error, --anisotropy.
#pragma once

#include <cstddef>

#include <CLI/CLI.hpp>

#include "aperture/terrain/view/quadtree_lod.h"
#include "aperture/terrain/view/texel_footprint.h"

namespace aal {

struct GpuOptions {
  int device = -1;  // Vulkan device index; -1: the best one
  size_t triangleBudget = kDefaultTriangleBudget;
  double lodErrorPixels = LodSettings{}.maxErrorPixels;  // 0: automatic
  int anisotropy = kDefaultFootprintProbes;
};

// --device, --triangles, --lod-error, --anisotropy. `panel`: the tool has a
// panel that changes the anisotropy while it runs (aal-view).
void addGpuOptions(CLI::App& app, GpuOptions& gpu, bool panel = false);

}  // namespace aal
