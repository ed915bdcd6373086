// A DEM in memory: heights on a regular grid with metric spacing, a void mask
// and optional georeferencing. docs/design.md §1. Always the whole DEM (or,
// with z empty, only its geometry: demGeometry); a rectangle of a DEM read in
// parts is a HeightWindow (terrain/height_window.h).
//
// Conventions: row 0 is the northern edge, column 0 the western edge, texel
// centres sit on the grid points. Heights are metres (z scale applied) above
// the DEM's own datum. Void (nodata) texels are filled for geometry and
// flagged in voidMask, so `z` never holds NaN or infinity.
#pragma once

#include <algorithm>
#include <cmath>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

class OGRSpatialReference;  // GDAL's CRS

namespace aal {

enum class CrsKind { None, Geographic, Projected };

struct GeoReference {
  CrsKind crs = CrsKind::None;
  int epsg = 0;  // 0 when the CRS has no EPSG code
  // The CRS exactly as the file gave it, as GDAL's object: writing it out as
  // WKT took 17-27 ms of every DEM's read (docs/performance.md). Null when
  // the grid is not georeferenced, or when only `epsg` names the CRS (then
  // the EPSG definition is used). Never modified: spatialReferenceOf
  // (terrain/io/gdal_session.h) hands out copies, which outputs carry.
  std::shared_ptr<const OGRSpatialReference> srs;
  std::string crsName;  // e.g. "WGS 84 / UTM zone 16N"; empty when unknown
  // CRS coordinates of the centre of texel (0, 0) and the spacing between
  // texel centres, in the CRS's own units. x grows east with the column, y
  // shrinks south with the row.
  double originX = 0, originY = 0, stepX = 0, stepY = 0;
  double linearUnitM = 1.0;  // metres per projected CRS unit (0.3048 for feet)
  // Geographic CRSs: degrees per CRS angular unit (0.9 for grads) and the
  // prime meridian's longitude east of Greenwich (2.337... for Paris).
  double angularUnitDeg = 1.0;
  double primeMeridianDeg = 0.0;
  // Geographic centre of the DEM (WGS84 degrees), when it can be known.
  bool hasCenter = false;
  double centerLatDeg = 0, centerLonDeg = 0;
};

struct Heightfield {
  int width = 0, height = 0;
  std::vector<float> z;  // width * height, row-major, metres
  // Empty when the DEM has no voids; else width * height flags, 1 = void.
  std::vector<uint8_t> voidMask;
  size_t voidCount = 0;

  // Metric spacing between texel centres. For geographic grids the x
  // spacing changes with latitude: rowCellSizeXM holds it per row, and
  // cellSizeXM is the value at the centre row.
  double cellSizeXM = 1.0, cellSizeYM = 1.0;
  std::vector<double> rowCellSizeXM;
  double zScale = 1.0;  // already applied to z; kept for the bake's metadata

  GeoReference geo;
  std::string source;  // path it was read from, or a description
  std::string format;  // e.g. "GeoTIFF", "SRTMHGT File Format", "synthetic"
  std::string driver;  // GDAL driver's short name ("GTiff"); empty when not from a file
  // The file's nodata value as stored, and its vertical unit as it names
  // it (empty when the file does not say; metres were then assumed).
  std::optional<double> nodata;
  std::string zUnitName;

  size_t texelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  size_t index(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(width) + static_cast<size_t>(x);
  }
  float at(int x, int y) const { return z[index(x, y)]; }
  bool isVoid(int x, int y) const { return !voidMask.empty() && voidMask[index(x, y)] != 0; }
  double cellSizeXAtRow(int row) const {
    return rowCellSizeXM.empty() ? cellSizeXM : rowCellSizeXM[static_cast<size_t>(row)];
  }
  // Bilinear height at the fractional texel position (col, row), clamped to
  // the grid: the surface through the texel centres that the bakers' rays,
  // the reference renderer and the viewer's camera all march or stand on.
  double bilinearHeight(double col, double row) const {
    // NaN passes std::clamp and would become an index: take texel 0.
    if (std::isnan(col)) col = 0.0;
    if (std::isnan(row)) row = 0.0;
    col = std::clamp(col, 0.0, static_cast<double>(width - 1));
    row = std::clamp(row, 0.0, static_cast<double>(height - 1));
    const int c0 = std::min(static_cast<int>(col), std::max(width - 2, 0));
    const int r0 = std::min(static_cast<int>(row), std::max(height - 2, 0));
    const int c1 = std::min(c0 + 1, width - 1), r1 = std::min(r0 + 1, height - 1);
    const double tc = col - c0, tr = row - r0;
    const double top = at(c0, r0) + (at(c1, r0) - at(c0, r0)) * tc;
    const double bottom = at(c0, r1) + (at(c1, r1) - at(c0, r1)) * tc;
    return top + (bottom - top) * tr;
  }
};

}  // namespace aal
