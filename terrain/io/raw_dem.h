// What the reader (terrain/io/dem_source.h) hands to loadDem: samples
// as stored in the file, voids flagged but not filled, no scale applied, and
// the georeferencing the file states. loadDem turns it into a Heightfield.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/georeference.h"

namespace aal {

struct RawDem {
  int width = 0, height = 0;
  // width * height samples, row 0 = north, in the file's vertical unit.
  // Void texels hold 0 and are flagged in voidMask.
  std::vector<float> z;
  std::vector<uint8_t> voidMask;  // width * height, 1 = void (nodata, NaN, +-inf)
  GeoReference geo;               // crs None when the file states no georeferencing
  double zUnitM = 1.0;            // metres per stored height unit, from the file
  bool zUnitFromFile = false;     // the file stated its vertical unit
  std::string format;             // GDAL driver's long name: "GeoTIFF", "Arc/Info ASCII Grid", ...
  std::string driver;             // GDAL driver's short name: "GTiff", "AAIGrid", ...
  std::string sampleType;         // as stored: "int16", "float32", ...
  std::optional<double> nodata;   // the file's nodata value, as stored
  std::string zUnitName;          // the file's vertical unit as it says it; empty when silent
  // metricSpacing(geo, width, height), when the reader found it already.
  std::optional<MetricSpacing> spacing;

  size_t texelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  // Allocates z and voidMask for width x height (call checkDemSize first).
  void allocate(int w, int h);
};

// Throws InputError("PATH: ...") unless 1 <= width, height <= kMaxDemSide and
// width * height <= maxTexels. Takes 64-bit sizes so that values read from a
// header are checked before any narrowing.
void checkDemSize(const std::string& path, int64_t width, int64_t height, size_t maxTexels);

// Stores a sample converted to float: NaN, +-inf and values out of float range
// become voids.
inline void storeSample(RawDem& dem, size_t index, double value) {
  const float f = static_cast<float>(value);
  if (!std::isfinite(f)) {
    dem.z[index] = 0.0f;
    dem.voidMask[index] = 1;
  } else {
    dem.z[index] = f;
  }
}

}  // namespace aal
