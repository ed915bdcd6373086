#include "geotiff_georeference.h"

#include <cmath>
#include <cstdlib>

#include "errors.h"
#include "georeference.h"

namespace aal {

namespace {

constexpr int kUserDefined = 32767;
constexpr double kPi = 3.14159265358979323846;

// EPSG unit codes (GeoTIFF spec, section 6.3.1.3/6.3.1.4).
constexpr int kMetre = 9001, kFoot = 9002, kUsSurveyFoot = 9003, kClarkeFoot = 9005,
              kKilometre = 9036;
constexpr int kRadian = 9101, kDegree = 9102, kArcMinute = 9103, kArcSecond = 9104, kGrad = 9105,
              kDegreeSupplier = 9122;

[[noreturn]] void inconsistent(const std::string& path, const std::string& problem) {
  throw InputError(path + ": inconsistent georeferencing: " + problem);
}

void warnIf(const std::function<void(const std::string&)>& warn, const std::string& message) {
  if (warn) warn(message);
}

std::optional<double> linearUnitM(int code) {
  switch (code) {
    case kMetre: return 1.0;
    case kFoot: return 0.3048;
    case kUsSurveyFoot: return 1200.0 / 3937.0;
    case kClarkeFoot: return 0.3047972654;
    case kKilometre: return 1000.0;
    default: return std::nullopt;
  }
}

std::optional<double> angularUnitDeg(int code) {
  switch (code) {
    case kRadian: return 180.0 / kPi;
    case kDegree:
    case kDegreeSupplier: return 1.0;
    case kArcMinute: return 1.0 / 60.0;
    case kArcSecond: return 1.0 / 3600.0;
    case kGrad: return 0.9;
    default: return std::nullopt;
  }
}

std::optional<double> parseNumber(const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end == begin) return std::nullopt;
  while (*end == ' ' || *end == '\t' || *end == '\n' || *end == '\r') ++end;
  if (*end != '\0') return std::nullopt;
  return value;
}

CrsKind crsKind(const std::string& path, const GeoTiffTags& tags,
                const std::function<void(const std::string&)>& warn) {
  if (tags.modelType) {
    switch (*tags.modelType) {
      case 1: break;
      case 2: break;
      case 3: inconsistent(path, "geocentric model type (3) is not supported");
      default:
        inconsistent(
            path, "unknown model type " + std::to_string(*tags.modelType) + " (GTModelTypeGeoKey)");
    }
    const bool projectedCode =
        tags.projectedType && *tags.projectedType != 0 && *tags.projectedType != kUserDefined;
    if (*tags.modelType == 2 && projectedCode) {
      inconsistent(path, "model type is geographic but ProjectedCSTypeGeoKey is " +
                             std::to_string(*tags.projectedType));
    }
    return *tags.modelType == 1 ? CrsKind::Projected : CrsKind::Geographic;
  }
  if (tags.projectedType) return CrsKind::Projected;
  if (tags.geographicType) return CrsKind::Geographic;
  warnIf(warn, path + " has GeoTIFF placement tags but no model type; georeferencing ignored");
  return CrsKind::None;
}

// Scale and the CRS position of raster point (rasterI, rasterJ), from
// ModelTransformation or ModelPixelScale + ModelTiepoint.
struct Placement {
  double scaleX = 0, scaleY = 0;  // CRS units per pixel; scaleY > 0 for north-up
  double rasterI = 0, rasterJ = 0, x = 0, y = 0;
};

Placement placement(const std::string& path, const GeoTiffTags& tags,
                    const std::function<void(const std::string&)>& warn) {
  Placement p;
  if (!tags.transformation.empty()) {
    const std::vector<double>& t = tags.transformation;
    if (t.size() != 16) {
      inconsistent(path,
                   "ModelTransformation has " + std::to_string(t.size()) + " values instead of 16");
    }
    if (t[1] != 0.0 || t[4] != 0.0) {
      inconsistent(path, "ModelTransformation rotates or shears the grid; not supported");
    }
    if (!tags.pixelScale.empty() || !tags.tiePoints.empty()) {
      warnIf(warn, path +
                       " has both ModelTransformation and pixel scale/tie points; "
                       "using ModelTransformation");
    }
    p.scaleX = t[0];
    p.scaleY = -t[5];
    p.x = t[3];
    p.y = t[7];
    return p;
  }
  if (tags.pixelScale.empty()) {
    inconsistent(path, tags.tiePoints.empty()
                           ? "GeoKeys without pixel scale, tie point or transformation"
                           : "tie points without pixel scale (ground control points) are "
                             "not supported");
  }
  if (tags.pixelScale.size() < 2) {
    inconsistent(path, "ModelPixelScale has " + std::to_string(tags.pixelScale.size()) +
                           " values instead of 3");
  }
  if (tags.tiePoints.size() < 6 || tags.tiePoints.size() % 6 != 0) {
    inconsistent(path, "ModelTiepoint has " + std::to_string(tags.tiePoints.size()) +
                           " values; need 6 per tie point");
  }
  if (tags.tiePoints.size() > 6) {
    warnIf(warn, path + " has " + std::to_string(tags.tiePoints.size() / 6) +
                     " tie points; using the first with the pixel scale");
  }
  p.scaleX = tags.pixelScale[0];
  p.scaleY = tags.pixelScale[1];
  p.rasterI = tags.tiePoints[0];
  p.rasterJ = tags.tiePoints[1];
  p.x = tags.tiePoints[3];
  p.y = tags.tiePoints[4];
  return p;
}

double geographicUnitDeg(const std::string& path, const GeoTiffTags& tags) {
  if (!tags.angularUnits) return 1.0;
  if (*tags.angularUnits == kUserDefined) {
    if (!tags.angularUnitSizeRad || !(*tags.angularUnitSizeRad > 0.0) ||
        !std::isfinite(*tags.angularUnitSizeRad)) {
      inconsistent(path, "user-defined angular unit without a positive GeogAngularUnitSizeGeoKey");
    }
    return *tags.angularUnitSizeRad * 180.0 / kPi;
  }
  const std::optional<double> unit = angularUnitDeg(*tags.angularUnits);
  if (!unit) {
    inconsistent(path, "unsupported angular unit code " + std::to_string(*tags.angularUnits));
  }
  return *unit;
}

double projectedUnitM(const std::string& path, const GeoTiffTags& tags, int epsg,
                      const std::function<void(const std::string&)>& warn) {
  if (!tags.linearUnits) {
    if (!utmUpsZoneFromEpsg(epsg)) {
      warnIf(warn, path + " names no linear unit (ProjLinearUnitsGeoKey); assuming metres");
    }
    return 1.0;
  }
  if (*tags.linearUnits == kUserDefined) {
    if (!tags.linearUnitSizeM || !(*tags.linearUnitSizeM > 0.0) ||
        !std::isfinite(*tags.linearUnitSizeM)) {
      inconsistent(path, "user-defined linear unit without a positive ProjLinearUnitSizeGeoKey");
    }
    return *tags.linearUnitSizeM;
  }
  const std::optional<double> unit = linearUnitM(*tags.linearUnits);
  if (!unit) {
    inconsistent(path, "unsupported linear unit code " + std::to_string(*tags.linearUnits));
  }
  return *unit;
}

int epsgCode(const std::optional<int>& key) {
  return key && *key > 0 && *key != kUserDefined ? *key : 0;
}

void readVerticalUnit(const std::string& path, const GeoTiffTags& tags,
                      const std::function<void(const std::string&)>& warn,
                      GeoTiffGeoreference& result) {
  if (!tags.verticalUnits) return;
  const std::optional<double> unit = linearUnitM(*tags.verticalUnits);
  if (!unit) {
    warnIf(warn, path + ": ignoring unsupported vertical unit code " +
                     std::to_string(*tags.verticalUnits) + "; heights taken as metres");
    return;
  }
  result.zUnitM = *unit;
  result.zUnitFromFile = true;
}

void readNodata(const std::string& path, const GeoTiffTags& tags,
                const std::function<void(const std::string&)>& warn, GeoTiffGeoreference& result) {
  if (!tags.gdalNodata) return;
  result.nodata = parseNumber(*tags.gdalNodata);
  if (!result.nodata) {
    warnIf(warn, path + ": ignoring GDAL_NODATA '" + *tags.gdalNodata + "': not a number");
  }
}

}  // namespace

GeoTiffGeoreference interpretGeoTiffTags(const std::string& path, const GeoTiffTags& tags,
                                         const std::function<void(const std::string&)>& warn) {
  GeoTiffGeoreference result;
  readNodata(path, tags, warn, result);
  readVerticalUnit(path, tags, warn, result);
  const bool placed =
      !tags.pixelScale.empty() || !tags.tiePoints.empty() || !tags.transformation.empty();
  if (!tags.hasGeoKeys && !placed) return result;  // a plain TIFF

  const CrsKind crs = crsKind(path, tags, warn);
  if (crs == CrsKind::None) return result;
  const Placement p = placement(path, tags, warn);
  if (!(std::isfinite(p.scaleX) && std::isfinite(p.scaleY) && std::isfinite(p.x) &&
        std::isfinite(p.y) && std::isfinite(p.rasterI) && std::isfinite(p.rasterJ))) {
    inconsistent(path, "pixel scale or tie point is not a finite number");
  }
  if (!(p.scaleX > 0.0) || p.scaleY == 0.0) {
    inconsistent(path, "pixel scale " + std::to_string(p.scaleX) + " x " +
                           std::to_string(p.scaleY) + " must be positive in x and non-zero in y");
  }
  if (tags.rasterType && *tags.rasterType != 1 && *tags.rasterType != 2) {
    warnIf(warn, path + ": unknown raster type " + std::to_string(*tags.rasterType) +
                     " (GTRasterTypeGeoKey); taken as PixelIsArea");
  }
  const bool pixelIsPoint = tags.rasterType && *tags.rasterType == 2;
  // Raster coordinates of texel (0, 0)'s centre: PixelIsArea puts integer
  // raster coordinates on texel corners.
  const double centre = pixelIsPoint ? 0.0 : 0.5;

  GeoReference& geo = result.geo;
  geo.crs = crs;
  result.southUp = p.scaleY < 0.0;
  const double firstRow = result.southUp ? static_cast<double>(tags.height - 1) : 0.0;
  geo.originX = p.x + (centre - p.rasterI) * p.scaleX;
  geo.originY = p.y - (firstRow + centre - p.rasterJ) * p.scaleY;
  geo.stepX = p.scaleX;
  geo.stepY = std::abs(p.scaleY);
  if (crs == CrsKind::Geographic) {
    const double unitDeg = geographicUnitDeg(path, tags);
    geo.originX *= unitDeg;
    geo.originY *= unitDeg;
    geo.stepX *= unitDeg;
    geo.stepY *= unitDeg;
    geo.epsg = epsgCode(tags.geographicType);
  } else {
    geo.epsg = epsgCode(tags.projectedType);
    geo.linearUnitM = projectedUnitM(path, tags, geo.epsg, warn);
  }
  return result;
}

}  // namespace aal
