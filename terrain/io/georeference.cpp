#include "aperture/terrain/io/georeference.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <memory>
#include <utility>

#include <ogr_spatialref.h>
#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Ellipsoid.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/Math.hpp>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/number_text.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

// Latitudes may pass the pole by rounding noise only.
constexpr double kLatitudeSlackDeg = 1e-9;
// 25 times the Earth's circumference.
constexpr double kMaxProjectedCoordinateM = 1e9;

const GeographicLib::Ellipsoid& wgs84() {
  static const GeographicLib::Ellipsoid ellipsoid(GeographicLib::Constants::WGS84_a(),
                                                  GeographicLib::Constants::WGS84_f());
  return ellipsoid;
}

// A longitude in [-180, 180), as docs/dem-input.md states: AngNormalize
// keeps +180 (its range is (-180, 180]), the antimeridian's centre.
double longitudeInRange(double degrees) {
  const double normalized = GeographicLib::Math::AngNormalize(degrees);
  return normalized >= 180.0 ? normalized - 360.0 : normalized;
}

[[noreturn]] void inconsistent(const std::string& path, const std::string& problem) {
  throw InputError(path + ": inconsistent georeferencing: " + problem);
}

void checkCellSize(const std::string& path, const char* axis, double cellM) {
  if (!(cellM >= kMinCellSizeM && cellM <= kMaxCellSizeM)) {
    inconsistent(path, std::string("cell size in ") + axis + " is " + numberText(cellM) +
                           " m, outside [" + numberText(kMinCellSizeM) + ", " +
                           numberText(kMaxCellSizeM) + "] m");
  }
}

MetricSpacing geographicSpacing(const std::string& path, const GeoReference& geo, int width,
                                int height) {
  const double unit = geo.angularUnitDeg;
  const double northDeg = geo.originY * unit;
  const double southDeg = (geo.originY - (height - 1) * geo.stepY) * unit;
  const double stepXDeg = geo.stepX * unit, stepYDeg = geo.stepY * unit;
  if (!(southDeg >= -90.0 - kLatitudeSlackDeg && northDeg <= 90.0 + kLatitudeSlackDeg)) {
    inconsistent(path, "rows span latitudes " + numberText(southDeg) + " to " +
                           numberText(northDeg) + " degrees, beyond +-90");
  }
  if ((width - 1) * stepXDeg > 360.0 + 1e-9) {
    inconsistent(path, "columns span " + numberText((width - 1) * stepXDeg) +
                           " degrees of longitude, more than 360");
  }
  MetricSpacing s;
  s.rowCellSizeXM.resize(static_cast<size_t>(height));
  for (int row = 0; row < height; ++row) {
    const double latDeg = std::clamp(northDeg - row * stepYDeg, -90.0, 90.0);
    // On a row at a pole the true spacing is 0; keep it positive so that
    // slopes stay finite.
    s.rowCellSizeXM[static_cast<size_t>(row)] =
        std::max(parallelArcM(latDeg, stepXDeg), kMinCellSizeM);
  }
  const double centerLatDeg = std::clamp(0.5 * (northDeg + southDeg), -90.0, 90.0);
  s.cellSizeXM = std::max(parallelArcM(centerLatDeg, stepXDeg), kMinCellSizeM);
  s.cellSizeYM =
      height > 1
          ? meridianArcM(std::clamp(southDeg, -90.0, 90.0), std::clamp(northDeg, -90.0, 90.0)) /
                (height - 1)
          : wgs84().MeridionalCurvatureRadius(centerLatDeg) * stepYDeg * kRadiansPerDegree;
  checkCellSize(path, "y", s.cellSizeYM);
  checkCellSize(path, "x", s.cellSizeXM);
  s.hasCenter = true;
  s.centerLatDeg = centerLatDeg;
  s.centerLonDeg =
      longitudeInRange((geo.originX + 0.5 * (width - 1) * geo.stepX) * unit + geo.primeMeridianDeg);
  return s;
}

// CRS coordinates to WGS84 longitude (x) and latitude (y), through PROJ.
class ToWgs84 {
 public:
  explicit ToWgs84(const OGRSpatialReference& source) {
    wgs84_.importFromEPSG(4326);
    wgs84_.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    transform_.reset(OGRCreateCoordinateTransformation(&source, &wgs84_));
  }
  bool valid() const { return transform_ != nullptr; }
  // Longitude and latitude in degrees, or nothing when PROJ cannot map the point.
  std::optional<std::pair<double, double>> operator()(double x, double y) const {
    if (!transform_->Transform(1, &x, &y)) return std::nullopt;
    if (!(std::isfinite(x) && std::isfinite(y) && std::abs(y) <= 90.0)) return std::nullopt;
    return std::make_pair(x, y);
  }

 private:
  OGRSpatialReference wgs84_;
  std::unique_ptr<OGRCoordinateTransformation> transform_;
};

// Ground distance in metres between two CRS points (geodesic on WGS84).
std::optional<double> groundDistanceM(const ToWgs84& toWgs84, double x0, double y0, double x1,
                                      double y1) {
  const auto a = toWgs84(x0, y0), b = toWgs84(x1, y1);
  if (!a || !b) return std::nullopt;
  double distance = 0;
  GeographicLib::Geodesic::WGS84().Inverse(a->second, a->first, b->second, b->first, distance);
  return distance;
}

MetricSpacing projectedSpacing(const std::string& path, const GeoReference& geo, int width,
                               int height) {
  if (!(geo.linearUnitM > 0.0 && std::isfinite(geo.linearUnitM))) {
    inconsistent(path, "linear unit of " + numberText(geo.linearUnitM) + " m");
  }
  MetricSpacing s;
  s.cellSizeXM = geo.stepX * geo.linearUnitM;
  s.cellSizeYM = geo.stepY * geo.linearUnitM;
  checkCellSize(path, "x", s.cellSizeXM);
  checkCellSize(path, "y", s.cellSizeYM);
  // No map of the Earth has coordinates beyond a few times its circumference.
  // Farther ones are a damaged georeference, and PROJ must never see them:
  // GDAL's Web Mercator shortcut wraps longitudes 360 degrees at a time, so
  // x = 1e18 m would loop for days.
  const double farthestM =
      std::max({std::abs(geo.originX), std::abs(geo.originX + width * geo.stepX),
                std::abs(geo.originY), std::abs(geo.originY - height * geo.stepY)}) *
      geo.linearUnitM;
  if (!(farthestM <= kMaxProjectedCoordinateM)) {
    inconsistent(path, "its corners lie " + numberText(farthestM) +
                           " m from the projection's origin, beyond any map of the Earth (" +
                           numberText(kMaxProjectedCoordinateM) + " m)");
  }
  const std::unique_ptr<OGRSpatialReference> srs = spatialReferenceOf(geo);
  if (!srs || srs->IsLocal()) return s;
  const ToWgs84 toWgs84(*srs);
  if (!toWgs84.valid()) return s;
  const double x = geo.originX + 0.5 * (width - 1) * geo.stepX;
  const double y = geo.originY - 0.5 * (height - 1) * geo.stepY;
  const auto centre = toWgs84(x, y);
  if (!centre) return s;
  s.hasCenter = true;
  s.centerLonDeg = longitudeInRange(centre->first);
  s.centerLatDeg = centre->second;
  // Ground spacing at the centre: conformal projections far from their
  // standard lines (Web Mercator above all) stretch the grid's nominal
  // spacing; the terrain's slopes need the ground's.
  const auto groundX = groundDistanceM(toWgs84, x - 0.5 * geo.stepX, y, x + 0.5 * geo.stepX, y);
  const auto groundY = groundDistanceM(toWgs84, x, y - 0.5 * geo.stepY, x, y + 0.5 * geo.stepY);
  if (!groundX || !groundY) return s;
  const double scaleX = s.cellSizeXM / *groundX, scaleY = s.cellSizeYM / *groundY;
  if (std::abs(scaleX - 1.0) > kProjectionScaleTolerance ||
      std::abs(scaleY - 1.0) > kProjectionScaleTolerance) {
    s.scaleNote = std::string("its projection (") + (srs->GetName() ? srs->GetName() : "?") +
                  ") stretches distances by " + numberText(scaleX) + " x " + numberText(scaleY) +
                  " at the DEM's centre: using the ground spacing there, " + numberText(*groundX) +
                  " x " + numberText(*groundY) + " m, instead of the grid's " +
                  numberText(s.cellSizeXM) + " x " + numberText(s.cellSizeYM) + " m";
    s.cellSizeXM = *groundX;
    s.cellSizeYM = *groundY;
    checkCellSize(path, "x", s.cellSizeXM);
    checkCellSize(path, "y", s.cellSizeYM);
  }
  return s;
}

}  // namespace

double parallelArcM(double latDeg, double dLonDeg) {
  return wgs84().CircleRadius(latDeg) * dLonDeg * kRadiansPerDegree;
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
    inconsistent(path, "pixel size " + numberText(geo.stepX) + " x " + numberText(geo.stepY) +
                           " is not positive and finite");
  }
  switch (geo.crs) {
    case CrsKind::Geographic: return geographicSpacing(path, geo, width, height);
    case CrsKind::Projected: return projectedSpacing(path, geo, width, height);
    case CrsKind::None: break;
  }
  inconsistent(path, "no coordinate reference system");
}

}  // namespace aal
