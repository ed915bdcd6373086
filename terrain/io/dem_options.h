// Options every DEM reader takes (terrain/io/dem_loader.h), and the size
// limits that protect against absurd or hostile files.
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <string>

namespace aal {

// Largest DEM side, in texels, and largest texel count accepted. Anything
// bigger is refused with InputError before memory is allocated: 2^31 texels
// already take 8 GiB of heights plus 2 GiB of void mask.
constexpr int kMaxDemSide = 65536;
constexpr size_t kMaxDemTexels = size_t{1} << 31;

// Largest height magnitude accepted, after the z scale: 1000 km, 50 times
// the Earth's relief. Beyond it a height is a fill value or wrong units.
constexpr double kMaxHeightM = 1e6;

// Cell size and z scale assumed when a file has no georeferencing and the
// user gave neither: one metre per texel, heights in metres.
constexpr double kDefaultCellSizeM = 1.0;
constexpr double kDefaultZScale = 1.0;

// Prints "warning: MESSAGE" on stderr: the default warning sink.
void warnOnStderr(const std::string& message);

struct DemLoadOptions {
  // Metric spacing between texel centres in x and y (> 0, finite). Overrides
  // whatever the file says; geographic grids then get a uniform spacing.
  std::optional<double> cellSizeM;
  // Metres per stored height unit (> 0, finite). Overrides the file's
  // vertical units (feet give 0.3048).
  std::optional<double> zScale;
  // Vertical exaggeration (> 0, finite): multiplies the z scale, so the
  // heights, the Heightfield's zScale and everything baked from them (the
  // aperture map records the z scale and the heights' checksum) see it
  // (aal-render / aal-view --exaggeration; docs/rendering.md).
  double exaggeration = 1.0;
  // Receives one message per suspicious but usable property of the file
  // (defaults assumed, extra bands ignored, ...). May be empty: no warnings.
  std::function<void(const std::string&)> warn = warnOnStderr;
  // Texel-count limit (<= kMaxDemTexels makes sense). Fuzzers lower it so
  // that hostile headers cannot ask for gigabytes.
  size_t maxTexels = kMaxDemTexels;
  // Whether GDAL's in-memory files (/vsimem/) may be read: programs that
  // make rasters in memory (the fuzzers) set it; no user's path names one,
  // and every other /vsi path but /vsicurl/, /vsizip/ and /vsigzip/ is
  // refused (terrain/io/input_file.h, gdalFileName).
  bool inMemoryFiles = false;
  // What to do when a read does not fit in the memory available: the end of
  // requireMemory's message. Empty: cut or coarsen the DEM, or bake it with
  // aal-bake --tile-size --low-memory. A caller that reads in windows
  // already says what helps it (aal-bake's tiled bakes).
  std::string memoryHint;
  // What the caller's work holds at its peak per DEM texel, the read's own
  // heights and void mask included (memory_budget.h: kRenderBytesPerTexel,
  // ...), and what that work is called ("a render"). The read of the whole
  // DEM checks that much against the memory available, so that a DEM whose
  // work would not fit is refused before its samples are read, not by the
  // allocator half-way. 0: the read alone.
  double peakBytesPerTexel = 0;
  std::string workName;
};

}  // namespace aal
