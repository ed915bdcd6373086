// An elevation raster opened through GDAL (docs/dem-input.md): what it is
// (size, georeferencing, units, nodata) known at once, its samples read a
// window at a time, so that a caller needs in memory only what it uses.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/raw_dem.h"

namespace aal {

// The supported formats and what is refused, for the tools' --help.
std::string demFormatsHelp();

class DemSource {
 public:
  // Opens `path` with GDAL and checks that it is a DEM: one band of real
  // numbers (extra bands are ignored with a warning, an alpha band becomes
  // voids), not a palette, RGB or complex image. Throws InputError("PATH:
  // ...") for missing, unreadable or unrecognised files, what is not a DEM
  // (saying how to get one band), sizes beyond options.maxTexels and rotated
  // grids.
  DemSource(const std::string& path, const DemLoadOptions& options);
  ~DemSource();
  DemSource(const DemSource&) = delete;
  DemSource& operator=(const DemSource&) = delete;

  const std::string& path() const { return path_; }
  int width() const { return description_.width; }
  int height() const { return description_.height; }
  // Everything but the samples: width, height, geo (of the whole raster),
  // zUnitM, format, driver, sampleType, nodata, zUnitName.
  // The CRS is found on a thread of its own while the caller reads: the
  // first call of description() or read() waits for it, gives its warnings
  // and throws InputError for a CRS aperture cannot place (geocentric).
  const RawDem& description() const;

  // Samples of columns [column, column + width) and rows [row, row + height)
  // (row 0 = north), scale and offset applied, voids (nodata, mask or alpha
  // zero, NaN, +-inf, beyond float) flagged; geo placed at the window's
  // texel (0, 0). Decodes on every core (GDAL_NUM_THREADS). Throws
  // std::invalid_argument for a window outside the raster, InputError for
  // truncated or corrupt data. Not thread-safe: one reader per thread.
  RawDem read(int column, int row, int width, int height) const;
  RawDem readAll() const { return read(0, 0, width(), height()); }
  // Samples read so far, every read's width x height: what a caller reading
  // the DEM in parts has read (docs/baking.md, tiled bakes).
  uint64_t texelsRead() const { return texelsRead_; }

 private:
  struct Impl;
  void settle() const;  // merges the CRS into description_, once

  std::string path_;
  mutable RawDem description_;
  mutable uint64_t texelsRead_ = 0;
  std::unique_ptr<Impl> impl_;
};

}  // namespace aal
