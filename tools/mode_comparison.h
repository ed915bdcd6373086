// Every shading mode against the CPU reference (docs/comparison.md): the same
// camera, sun and sky rendered by the GPU in each mode and by the reference ray
// tracer, with the relative RMSE of linear radiance over the terrain and error
// maps as images; and, along a slow camera pan, each one's shimmer
// (terrain/reference/shimmer.h).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/terrain/reference/reference_renderer.h"

namespace aal {

class TerrainScene;

// One GPU rendering to compare: a shading mode, with or without the
// obscurance passes (W).
struct ComparedMode {
  std::string name;
  ShadingMode mode = ShadingMode::Approx;
  bool obscurance = true;
  // Called just before this mode's rendering when set (aal-render gives the
  // scene each of several horizon maps this way).
  std::function<void()> prepare;
};

// approx, exact (with W when the settings enable it), approx without W,
// and the two no-aperture baselines.
std::vector<ComparedMode> defaultComparedModes(const FrameSettings& settings);

struct ComparisonOptions {
  int sunRays = 16;
  int skyRays = 64;
  // Per axis (ReferenceSettings::subpixels): 4 has converged, docs/comparison.md.
  int subpixels = 4;
  // Ground albedo of both renderers (the GPU gets it as FrameSettings::
  // albedoValue): the reference knows only a constant.
  glm::vec3 albedo{0.2f};
  bool interreflection = true;
  // The GPU modes' points per pixel per axis (engine/supersampling.h): the
  // renderer is `supersample` times the reference's width and height, and
  // each mode's frame is averaged down to it.
  uint32_t supersample = 1;
  // Along a pan: each mode's frames accumulated over the frames before
  // them (TerrainRenderer::renderAccumulated, started with
  // startAccumulation), as aal-render's image sequences draw them.
  bool temporal = false;
};

// The reference's settings for a GPU frame: same camera, sun, sky, haze,
// the given size, ray counts and albedo, the sky model as background.
ReferenceSettings referenceSettingsFor(const FrameSettings& settings, uint32_t width,
                                       uint32_t height, const ComparisonOptions& options);

// The reference image as a frame: linear radiance and its tone-mapped display
// (tone_map.h toneMap with `exposure`), for writeFrame().
FrameResult referenceFrame(const ReferenceImage& image, float exposure);

struct ModeError {
  std::string mode;
  double relativeRmse = 0;       // sqrt(sum |gpu - ref|^2 / sum |ref|^2) over the mask
  double meanRelativeError = 0;  // mean of |Y_gpu - Y_ref| / Y_ref over the mask (luminance)
  FrameResult frame;             // the GPU's frame, linear included
  // Along a pan (measureShimmer): the mean |Y(t+1) - 2 Y(t) + Y(t-1)| of
  // linear luminance (kcd/m²) over the reference's interior mask.
  std::optional<double> shimmer;
  // Along a pan: the mean over its frames of the relative RMSE against each
  // frame's reference.
  std::optional<double> panRelativeRmse;
};

struct Comparison {
  ReferenceImage reference;
  std::vector<uint8_t> mask;  // terrain pixels away from the silhouette
  std::vector<ModeError> modes;
  double referenceSeconds = 0;
  // Along a pan (measureShimmer): the reference's own shimmer, and the
  // number of frames.
  std::optional<double> referenceShimmer;
  int panFrames = 0;
};

// The geometric error (pixels) the GPU modes are drawn with, at most.
constexpr double kComparisonLodErrorPixels = 0.25;

// Renders the reference and each of `modes` at the renderer's size, both
// with options.albedo as the ground's albedo; the GPU with a mesh within
// kComparisonLodErrorPixels of the DEM. `progress` (may be empty) gets
// the reference's finished fraction.
Comparison compareModes(TerrainRenderer& renderer, const TerrainScene& scene,
                        const Heightfield& field, const FrameSettings& settings,
                        const std::vector<ComparedMode>& modes, const ComparisonOptions& options,
                        const std::function<void(double)>& progress = {});

// The shimmer of the reference and of each of `modes` (in c.modes' order,
// as compareModes made them) along a slow pan through `cameras` (at least
// three): each frame rendered by the reference and by every mode, with the
// settings compareModes gives them, and the temporal second difference
// taken over the pixels of the reference's interior mask in all three
// frames (ShimmerMeter). Sets c.referenceShimmer, c.panFrames and each
// mode's shimmer and pan error. With options.temporal each mode's frames
// are one accumulated sequence. `progress` (may be empty) gets the
// finished fraction.
// Throws std::invalid_argument for fewer than three cameras or modes that
// are not c's.
void measureShimmer(Comparison& c, TerrainRenderer& renderer, const TerrainScene& scene,
                    const Heightfield& field, const FrameSettings& settings,
                    const std::vector<ComparedMode>& modes, const ComparisonOptions& options,
                    const std::vector<Camera>& cameras,
                    const std::function<void(double)>& progress = {});

// The names of the files writeComparison writes into its folder, one
// definition for the writer and for aal-render's check of its paths before
// any work (tools/tool_paths.h): the reference's, each mode's and the table.
constexpr const char* kComparisonReferenceLinearName = "reference.exr";
constexpr const char* kComparisonReferenceImageName = "reference.png";
constexpr const char* kComparisonTableName = "errors.csv";
std::string comparisonImageName(const std::string& mode);       // NAME.png
std::string comparisonErrorImageName(const std::string& mode);  // NAME-error.png
// Every file for modes named `modeNames`, in the order they are written.
std::vector<std::string> comparisonFileNames(const std::vector<std::string>& modeNames);

// Writes into `folder` (created if missing): reference.exr (linear) and
// reference.png (tone-mapped with `exposure`), NAME.png and NAME-error.png
// (per-pixel |Y_gpu - Y_ref| / Y_ref, black 0 to white >= 50 %, sky blue) for
// each mode, and errors.csv (name, relative RMSE, mean relative error; after
// measureShimmer also each one's shimmer, its ratio to the reference's and
// its mean error along the pan, and a row for the reference itself): comparisonFileNames. Files go
// through temporary files renamed into place.
void writeComparison(const std::string& folder, const Comparison& comparison, float exposure);

}  // namespace aal
