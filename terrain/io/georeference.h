// Metric spacing and geographic centre of a georeferenced grid (docs/design.md
// §1, §3; docs/dem-input.md). Geographic grids are measured on
// the WGS84 ellipsoid with GeographicLib; projected grids use their pixel
// scale times the CRS's linear unit, checked against the geodesic distance
// at the centre; the centre of any CRS comes from PROJ (through GDAL's OGR).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "aperture/terrain/heightfield.h"

namespace aal {

// Metric cell sizes outside this range are refused as absurd (InputError).
constexpr double kMinCellSizeM = 1e-6;
constexpr double kMaxCellSizeM = 1e7;

struct MetricSpacing {
  // Spacing between texel centres, metres. For geographic grids cellSizeXM
  // is the east-west spacing at the centre latitude and rowCellSizeXM holds
  // it for every row (north to south); cellSizeYM is the mean north-south
  // spacing over the grid.
  double cellSizeXM = 0, cellSizeYM = 0;
  std::vector<double> rowCellSizeXM;  // empty for projected grids
  bool hasCenter = false;             // centre known in WGS84 lat/lon
  double centerLatDeg = 0, centerLonDeg = 0;
  // Set when the projection's scale at the centre differs from 1 by more
  // than kProjectionScaleTolerance and the ground spacing replaced the
  // grid's: says so, with both, for a warning.
  std::string scaleNote;
};

// Projected grids whose ground spacing at the centre differs from the
// nominal one by more than this fraction get the ground spacing (UTM's
// scale stays within 0.1 %, Web Mercator's is 1/cos(latitude)).
constexpr double kProjectionScaleTolerance = 0.01;

// Spacing and centre of a width x height grid described by `geo` (crs must
// be Geographic or Projected; geo.stepX and geo.stepY > 0). Throws
// InputError("PATH: inconsistent georeferencing: ...") when the grid leaves
// the valid latitude range, spans more than 360 degrees of longitude, has a
// non-positive or non-finite step or an absurd metric cell size. Projected
// grids whose CRS PROJ cannot map to WGS84 (local or engineering CRSs) have
// no centre.
MetricSpacing metricSpacing(const std::string& path, const GeoReference& geo, int width,
                            int height);

// East-west distance between two points dLonDeg apart on the parallel at
// latDeg, metres (WGS84 circle radius times the angle).
double parallelArcM(double latDeg, double dLonDeg);
// North-south distance along a meridian between two latitudes, metres
// (WGS84 meridian arc).
double meridianArcM(double lat0Deg, double lat1Deg);

}  // namespace aal
