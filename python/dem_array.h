// A DEM handed over from Python as an array (docs/python.md): heights,
// voids and metric spacing, turned into the Heightfield the tools would load
// from a file, by the loader's own steps (terrain/io/dem_loader.h).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/georeference.h"

namespace aal::python {

// The metric spacing of the DEM's texel centres, as aperture.CellSize holds
// it: x east-west at the centre row, y north-south, and for geographic grids
// x per row, north to south (georeference.h, MetricSpacing).
struct CellSpacing {
  double x = 1.0, y = 1.0;
  std::vector<double> rows;                     // empty: x for every row
  std::optional<std::array<double, 2>> center;  // WGS84 latitude, longitude (degrees)
};

struct DemArray {
  int width = 0, height = 0;
  std::vector<float> z;        // width * height, row 0 north; non-finite = void
  std::vector<uint8_t> voids;  // empty, or width * height flags (1 = void)
  CellSpacing spacing;
  double zScale = 1.0;        // metres per height unit
  double exaggeration = 1.0;  // aal-render --exaggeration
};

// Name of the array in messages ("dem: every texel is void ...").
inline constexpr const char* kDemName = "dem";

// The heightfield aal-bake, aal-relief and aal-render would load from a file
// holding these samples with this spacing: heights times the z scale,
// non-finite ones and flagged ones void, voids filled with the nearest valid
// height (heightfieldFromRaw). A uniform spacing without a centre goes in as
// --cell-size does; any other as the spacing a georeferenced file's reader
// finds (RawDem::spacing), so a geographic DEM's per-row x spacing is kept.
// Throws InputError ("dem: ...") for a DEM the tools would refuse.
Heightfield toHeightfield(DemArray dem);

// What aal::metricSpacing gives for a grid placed by a CRS (WKT, "EPSG:n",
// or anything OGRSpatialReference::SetFromUserInput reads; empty: none, the
// coordinates taken as metres, as the DEM reader does) and a GDAL
// geotransform, plus the metres per height unit of a vertical CRS (1 when it
// names none). Throws InputError for what the DEM reader refuses (rotated
// grids, geocentric CRSs, inconsistent georeferencing).
struct GridSpacing {
  CellSpacing spacing;
  double zUnitM = 1.0;
  bool zUnitFromCrs = false;
};
GridSpacing gridSpacing(const std::string& crs, const std::array<double, 6>& geoTransform,
                        int width, int height);

}  // namespace aal::python
