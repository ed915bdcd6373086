// aal-render's paths, checked before any work (tools/tool_paths.h).
#pragma once

#include <optional>

#include "aperture/tools/render/image_sequence.h"
#include "aperture/tools/render/render_options.h"

namespace aal {

// Every path the run writes against every file it reads, before any work:
// -o, or a sequence's frames and its movie, or the files of --compare; the
// DEM with the files GDAL reads for it (a VRT's sources), a tiled aperture
// map's files (docs/dem-input.md, "Outputs"). InputError when two meet or
// an output cannot be written.
void checkRenderPaths(const RenderOptions& o, const std::optional<ImageSequence>& sequence);

}  // namespace aal
