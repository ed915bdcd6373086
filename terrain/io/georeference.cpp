#include "georeference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include "errors.h"

namespace aal {

namespace {

constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
// Latitudes may pass the pole by rounding noise only.
constexpr double kLatitudeSlackDeg = 1e-9;

const GeographicLib::Ellipsoid& wgs84() {
  static const GeographicLib::Ellipsoid ellipsoid(GeographicLib::Constants::WGS84_a(),
                                                  GeographicLib::Constants::WGS84_f());
  return ellipsoid;
}

std::string number(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.10g", value);
  return text;
}

[[noreturn]] void inconsistent(const std::string& path, const std::string& problem) {
  throw InputError(path + ": inconsistent georeferencing: " + problem);
}

void checkCellSize(const std::string& path, const char* axis, double cellM) {
  if (!(cellM >= kMinCellSizeM && cellM <= kMaxCellSizeM)) {
    inconsistent(path, std::string("cell size in ") + axis + " is " + number(cellM) +
                           " m, outside [" + number(kMinCellSizeM) + ", " + number(kMaxCellSizeM) +
                           "] m");
  }
}

MetricSpacing geographicSpacing(const std::string& path, const GeoReference& geo, int width,
                                int height) {
  const double northDeg = geo.originY;
  const double southDeg = geo.originY - (height - 1) * geo.stepY;
  if (!(southDeg >= -90.0 - kLatitudeSlackDeg && northDeg <= 90.0 + kLatitudeSlackDeg)) {
    inconsistent(path, "rows span latitudes " + number(southDeg) + " to " + number(northDeg) +
                           " degrees, beyond +-90");
  }
  if ((width - 1) * geo.stepX > 360.0 + 1e-9) {
    inconsistent(path, "columns span " + number((width - 1) * geo.stepX) +
                           " degrees of longitude, more than 360");
  }
  MetricSpacing s;
  s.rowCellSizeXM.resize(static_cast<size_t>(height));
  for (int row = 0; row < height; ++row) {
    const double latDeg = std::clamp(geo.originY - row * geo.stepY, -90.0, 90.0);
    // On a row at a pole the true spacing is 0; keep it positive so that
    // slopes stay finite.
    s.rowCellSizeXM[static_cast<size_t>(row)] =
        std::max(parallelArcM(latDeg, geo.stepX), kMinCellSizeM);
  }
  const double centerLatDeg = std::clamp(0.5 * (northDeg + southDeg), -90.0, 90.0);
  s.cellSizeXM = std::max(parallelArcM(centerLatDeg, geo.stepX), kMinCellSizeM);
  s.cellSizeYM =
      height > 1
          ? meridianArcM(std::clamp(southDeg, -90.0, 90.0), std::clamp(northDeg, -90.0, 90.0)) /
                (height - 1)
          : wgs84().MeridionalCurvatureRadius(centerLatDeg) * geo.stepY * kDegToRad;
  checkCellSize(path, "y", s.cellSizeYM);
  checkCellSize(path, "x", s.cellSizeXM);
  s.hasCenter = true;
  s.centerLatDeg = centerLatDeg;
  s.centerLonDeg = GeographicLib::Math::AngNormalize(geo.originX + 0.5 * (width - 1) * geo.stepX);
  return s;
}

MetricSpacing projectedSpacing(const std::string& path, const GeoReference& geo, int width,
                               int height) {
  if (!(geo.linearUnitM > 0.0 && std::isfinite(geo.linearUnitM))) {
    inconsistent(path, "linear unit of " + number(geo.linearUnitM) + " m");
  }
  MetricSpacing s;
  s.cellSizeXM = geo.stepX * geo.linearUnitM;
  s.cellSizeYM = geo.stepY * geo.linearUnitM;
  checkCellSize(path, "x", s.cellSizeXM);
  checkCellSize(path, "y", s.cellSizeYM);
  const std::optional<UtmUpsZone> zone = utmUpsZoneFromEpsg(geo.epsg);
  if (zone) {
    const double xM = (geo.originX + 0.5 * (width - 1) * geo.stepX) * geo.linearUnitM;
    const double yM = (geo.originY - 0.5 * (height - 1) * geo.stepY) * geo.linearUnitM;
    try {
      GeographicLib::UTMUPS::Reverse(zone->zone, zone->north, xM, yM, s.centerLatDeg,
                                     s.centerLonDeg);
      s.hasCenter = true;
    } catch (const GeographicLib::GeographicErr&) {
      const std::string name =
          zone->zone == 0 ? std::string("UPS") : "UTM zone " + std::to_string(zone->zone);
      inconsistent(path, "centre (" + number(xM) + ", " + number(yM) + ") m lies outside " + name +
                             (zone->north ? " north" : " south") + " (EPSG " +
                             std::to_string(geo.epsg) + ")");
    }
  }
  return s;
}

}  // namespace

double parallelArcM(double latDeg, double dLonDeg) {
  return wgs84().CircleRadius(latDeg) * dLonDeg * kDegToRad;
}

double meridianArcM(double lat0Deg, double lat1Deg) {
  return std::abs(wgs84().MeridianDistance(lat1Deg) - wgs84().MeridianDistance(lat0Deg));
}

MetricSpacing metricSpacing(const std::string& path, const GeoReference& geo, int width,
                            int height) {
  if (!(std::isfinite(geo.originX) && std::isfinite(geo.originY))) {
    inconsistent(path, "origin is not a finite number");
  }
  if (!(geo.stepX > 0.0 && geo.stepY > 0.0 && std::isfinite(geo.stepX) &&
        std::isfinite(geo.stepY))) {
    inconsistent(path, "pixel size " + number(geo.stepX) + " x " + number(geo.stepY) +
                           " is not positive and finite");
  }
  switch (geo.crs) {
    case CrsKind::Geographic: return geographicSpacing(path, geo, width, height);
    case CrsKind::Projected: return projectedSpacing(path, geo, width, height);
    case CrsKind::None: break;
  }
  inconsistent(path, "no coordinate reference system");
}

std::optional<UtmUpsZone> utmUpsZoneFromEpsg(int epsg) {
  if (epsg == 32661) return UtmUpsZone{0, true};
  if (epsg == 32761) return UtmUpsZone{0, false};
  if (epsg >= 32601 && epsg <= 32660) return UtmUpsZone{epsg - 32600, true};
  if (epsg >= 32701 && epsg <= 32760) return UtmUpsZone{epsg - 32700, false};
  if (epsg >= 26901 && epsg <= 26923) return UtmUpsZone{epsg - 26900, true};
  if (epsg >= 25828 && epsg <= 25838) return UtmUpsZone{epsg - 25800, true};
  return std::nullopt;
}

}  // namespace aal
