// aal-render's command line: every option it takes, defined in the order of
// its --help, with the shared groups of tools/options/ (docs/cli.md).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <glm/vec3.hpp>

#include "aperture/terrain/light/atmosphere.h"
#include "aperture/terrain/light/obscurance.h"
#include "aperture/tools/mode_comparison.h"
#include "aperture/tools/options/camera_options.h"
#include "aperture/tools/options/dem_units_options.h"
#include "aperture/tools/options/gpu_options.h"
#include "aperture/tools/options/output_options.h"
#include "aperture/tools/options/sun_options.h"

namespace aal {

struct RenderOptions {
  std::string dem, aperture, output, albedo;
  // Directional horizons (aal-bake --horizons); --compare takes several.
  std::vector<std::string> horizons;
  std::string size = "1280x720";
  CameraOptions camera;
  SunOptions sun;
  double turbidity = kDefaultTurbidity;
  std::optional<double> ev100;
  std::optional<double> visibilityKm;
  std::optional<double> waterLevelM;
  std::string mode = "approx";
  DemUnitsOptions units;
  double exaggeration = 1.0;
  GpuOptions gpu;
  uint32_t supersample = 1;
  std::string temporal = "auto";  // --temporal: accumulate a sequence's frames (auto|on|off)
  uint32_t maxTileTexels = 0;
  bool stats = false;
  int passProfile = 0;  // --pass-profile N: frames with each step submitted alone
  ProgressOptions report;
  std::string albedoValue;
  std::optional<double> obscuranceRadiusM;
  int obscuranceSamples = ObscuranceSettings{}.samples, obscuranceSteps = 1;
  bool noObscurance = false;
  std::string background = "sky";  // --background sky|transparent
  std::optional<double> baseDepthM;
  std::string baseColor = "0.35,0.3,0.25";
  std::string compare;  // folder for --compare
  // Image sequences: --camera-path and/or --time-range START END, --frames N.
  std::string cameraPath;
  std::vector<std::string> timeRange;
  std::optional<int> frames;
  double fps = 30;
  int referenceSunRays = ComparisonOptions{}.sunRays;
  int referenceSkyRays = ComparisonOptions{}.skyRays;
  int referenceSubpixels = ComparisonOptions{}.subpixels;  // per axis
};

// The CPU ray tracer's name on --mode (not a GPU shading mode).
constexpr const char* kReferenceMode = "reference";

// Every option of aal-render into `o`, in the order --help lists them.
void addRenderOptions(CLI::App& app, RenderOptions& o);

// --albedo-value, --base-color: one grey value or R,G,B, each in [0, 1];
// InputError naming `option` otherwise.
glm::vec3 parseAlbedoValue(const std::string& text, const std::string& option = "--albedo-value");

}  // namespace aal
