#include "aperture/tools/render/render_paths.h"

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include "aperture/terrain/errors.h"
#include "aperture/tools/mode_comparison.h"
#include "aperture/tools/render/comparison_run.h"
#include "aperture/tools/render_sequence.h"
#include "aperture/tools/tool_paths.h"

namespace aal {
namespace {

// requireWritableOutput for a file in `folder`, which writeComparison
// creates with its parents when missing: the nearest folder that exists
// must take it.
void requireWritableComparison(const std::string& folder, const std::string& file) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(folder, error) && !fs::is_directory(folder, error)) {
    throw InputError("--compare " + folder +
                     " is a file: --compare names a folder for its images; give a folder");
  }
  fs::path missing = fs::absolute(folder, error) / file;
  while (missing.has_parent_path() && missing.parent_path() != missing.root_path() &&
         !fs::exists(missing.parent_path(), error)) {
    missing = missing.parent_path();
  }
  requireWritableOutput(missing.string());
}

// The files the run reads.
NamedPaths renderInputs(const RenderOptions& o) {
  NamedPaths inputs = inputFiles("DEM", o.dem, /*raster=*/true);
  append(inputs, inputFiles("--aperture", o.aperture));
  inputs.push_back({"--albedo", o.albedo});
  inputs.push_back({"--camera-path", o.cameraPath});
  for (const std::string& path : o.horizons) inputs.push_back({"--horizons", path});
  return inputs;
}

}  // namespace

void checkRenderPaths(const RenderOptions& o, const std::optional<ImageSequence>& sequence) {
  const NamedPaths inputs = renderInputs(o);
  NamedPaths outputs;
  std::vector<OutputFamily> families;
  if (!o.compare.empty()) {
    for (const std::string& name : comparisonFileNames(comparedModeNames(o))) {
      outputs.push_back({"--compare", (std::filesystem::path(o.compare) / name).string(),
                         "written by --compare " + o.compare});
    }
  } else {
    outputs.push_back({"-o", o.output});
    if (sequence) {
      families.push_back(sequenceFrameFiles(o.output, sequence->frames));
      // ffmpeg writes it only when installed (renderSequence).
      if (const std::string mp4 = moviePath(o); !mp4.empty() && findFfmpeg()) {
        outputs.push_back({"-o", mp4, "the movie of the frames"});
      }
    }
  }
  checkDistinctFiles(inputs, outputs, families);
  for (const RunPath& out : outputs) {
    if (out.option == "--compare") {
      requireWritableComparison(o.compare, std::filesystem::path(out.path).filename().string());
    } else {
      requireWritableOutput(out.path);
    }
  }
  for (const OutputFamily& frames : families) {
    requireWritableFamily(frames,
                          std::filesystem::path(sequenceFramePath(o.output, 0, sequence->frames))
                              .filename()
                              .string());
  }
}

}  // namespace aal
