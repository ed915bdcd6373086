// Metric spacing and geographic centre of a georeferenced grid (DESIGN §1,
// §3 "Geographic DEMs"). Geographic grids are measured on the WGS84
// ellipsoid with GeographicLib; projected grids use their pixel scale times
// the CRS's linear unit; UTM/UPS grids get their centre from
// GeographicLib::UTMUPS.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "heightfield.h"

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
};

// Spacing and centre of a width x height grid described by `geo` (crs must
// be Geographic or Projected; geo.stepX and geo.stepY > 0). Throws
// InputError("PATH: inconsistent georeferencing: ...") when the grid leaves
// the valid latitude range, spans more than 360 degrees of longitude, has a
// non-positive or non-finite step or an absurd metric cell size, or has a
// UTM/UPS code whose centre is outside that zone's valid range.
MetricSpacing metricSpacing(const std::string& path, const GeoReference& geo, int width,
                            int height);

// East-west distance between two points dLonDeg apart on the parallel at
// latDeg, metres (WGS84 circle radius times the angle).
double parallelArcM(double latDeg, double dLonDeg);
// North-south distance along a meridian between two latitudes, metres
// (WGS84 meridian arc).
double meridianArcM(double lat0Deg, double lat1Deg);

struct UtmUpsZone {
  int zone = 0;  // 1..60 for UTM, 0 for UPS
  bool north = true;
};
// The UTM/UPS zone an EPSG code names: WGS84 UTM 326zz/327zz, UPS 32661
// (north) / 32761 (south), NAD83 UTM 269zz (zones 1-23) and ETRS89 UTM
// 258zz (zones 28-38), whose ellipsoid (GRS80) matches WGS84 to well under
// a millimetre. Empty for any other code.
std::optional<UtmUpsZone> utmUpsZoneFromEpsg(int epsg);

}  // namespace aal
