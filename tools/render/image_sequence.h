// aal-render's image sequences (--camera-path, --time-range, --frames): the
// options checked, each frame's camera and sun, and the frames and their
// movie rendered (docs/rendering.md, "Image sequences and movies"). The
// frames' file names and the MP4 encoding are tools/render_sequence.h.
#pragma once

#include <optional>
#include <string>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/engine/terrain_scene.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/light/solar_position.h"
#include "aperture/terrain/view/camera_path.h"
#include "aperture/tools/render/render_options.h"
#include "aperture/tools/tool_paths.h"

namespace aal {

// A sequence's checks and its time range, before any work; its camera path
// is read once the paths are checked (checkedRequest).
struct ImageSequence {
  std::optional<CameraPath> path;
  std::optional<UtcTime> start, end;
  int frames = 0;
  // --temporal: the frames accumulated (TerrainRenderer::renderAccumulated).
  bool temporal = false;
};

// The sequence the options ask for, none without --camera-path and
// --time-range; InputError when they contradict each other or the rest
// (`reference`: --mode reference).
std::optional<ImageSequence> imageSequenceOf(const RenderOptions& o, bool reference);

// Frame i of a sequence: the camera along the path, the sun at the frame's
// time.
void setSequenceFrame(const RenderOptions& o, const ImageSequence& seq, const Heightfield& field,
                      int i, FrameSettings& settings);

// The MP4 a sequence of PNG frames makes with ffmpeg: OUT.mp4 (none for
// EXR frames).
std::string moviePath(const RenderOptions& o);

// The frames of a sequence of `count`, OUT-0001.png ..., by name in -o's
// folder.
OutputFamily sequenceFrameFiles(const std::string& output, int count);

// --camera-path / --time-range: frames OUT-0001.ext ... and, for PNG frames
// with ffmpeg installed, OUT.mp4 (docs/rendering.md). The renderer re-lays
// the horizons when a frame's sun needs it (TerrainRenderer::record).
// Returns the exit code.
int renderSequence(const RenderOptions& o, const ImageSequence& seq, const Heightfield& field,
                   const TerrainScene& scene, TerrainRenderer& renderer, FrameSettings settings);

}  // namespace aal
