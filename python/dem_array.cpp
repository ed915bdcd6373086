#include "aperture/python/dem_array.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>

#include <ogr_spatialref.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/raw_dem.h"
#include "aperture/terrain/number_text.h"
#include "aperture/terrain/units.h"

namespace aal::python {

namespace {

// The range the DEM reader accepts for a metric cell size (georeference.h),
// checked here because a spacing handed over is not measured again.
void checkCellSize(const char* what, double metres) {
  if (!(metres >= kMinCellSizeM && metres <= kMaxCellSizeM)) {
    throw InputError(std::string("cell_size: ") + what + " must be in [" +
                     numberText(kMinCellSizeM) + ", " + numberText(kMaxCellSizeM) +
                     "] metres, got " + numberText(metres));
  }
}

void checkSpacing(const CellSpacing& s, int height) {
  checkCellSize("the x spacing", s.x);
  checkCellSize("the y spacing", s.y);
  if (!s.rows.empty()) {
    if (s.rows.size() != static_cast<size_t>(height)) {
      throw InputError("cell_size: the x spacing per row has " + std::to_string(s.rows.size()) +
                       " values; the DEM has " + std::to_string(height) + " rows");
    }
    for (const double x : s.rows) checkCellSize("every row's x spacing", x);
  }
  if (s.center && !(std::abs((*s.center)[0]) <= 90.0 && std::isfinite((*s.center)[1]))) {
    throw InputError(
        "cell_size: the centre must be a latitude in [-90, 90] and a finite "
        "longitude, got " +
        numberText((*s.center)[0]) + ", " + numberText((*s.center)[1]));
  }
}

}  // namespace

Heightfield toHeightfield(DemArray dem) {
  checkDemSize(kDemName, dem.width, dem.height, kMaxDemTexels);
  const size_t texels = static_cast<size_t>(dem.width) * static_cast<size_t>(dem.height);
  if (dem.z.size() != texels || (!dem.voids.empty() && dem.voids.size() != texels)) {
    throw std::invalid_argument("dem: the heights or voids do not match the DEM's size");
  }
  checkSpacing(dem.spacing, dem.height);
  if (!(dem.zScale > 0.0 && std::isfinite(dem.zScale))) {
    throw InputError("z_scale must be a positive number, got " + numberText(dem.zScale));
  }

  RawDem raw;
  raw.width = dem.width;
  raw.height = dem.height;
  raw.z = std::move(dem.z);
  raw.voidMask = dem.voids.empty() ? std::vector<uint8_t>(texels, 0) : std::move(dem.voids);
  // What the reader's storeSample does with each sample: non-finite ones
  // are voids holding 0 (scaleHeights flags them too, but not the flagged
  // ones' heights, which must not reach the fill).
  for (size_t i = 0; i < texels; ++i) {
    if (raw.voidMask[i] != 0 || !std::isfinite(raw.z[i])) {
      raw.voidMask[i] = 1;
      raw.z[i] = 0.0f;
    }
  }
  raw.format = "array";
  raw.sampleType = "float32";

  DemLoadOptions load;
  load.zScale = dem.zScale;
  load.exaggeration = dem.exaggeration;
  load.warn = nullptr;  // the array has no file whose defaults could be assumed
  const CellSpacing& s = dem.spacing;
  if (s.rows.empty() && !s.center && s.x == s.y) {
    load.cellSizeM = s.x;  // as aal-bake --cell-size on a file without georeferencing
  } else {
    // As the reader of a georeferenced file hands its spacing over
    // (RawDem::spacing, applySpacing in dem_loader.cpp).
    MetricSpacing spacing;
    spacing.cellSizeXM = s.x;
    spacing.cellSizeYM = s.y;
    spacing.rowCellSizeXM = s.rows;
    if (s.center) {
      spacing.hasCenter = true;
      spacing.centerLatDeg = (*s.center)[0];
      spacing.centerLonDeg = (*s.center)[1];
    }
    raw.geo.crs = s.rows.empty() ? CrsKind::Projected : CrsKind::Geographic;
    raw.spacing = std::move(spacing);
  }
  return heightfieldFromRaw(std::move(raw), kDemName, load);
}

GridSpacing gridSpacing(const std::string& crs, const std::array<double, 6>& gt, int width,
                        int height) {
  checkDemSize(kDemName, width, height, kMaxDemTexels);
  // The reader's describeTransform (terrain/io/dem_source.cpp).
  if (gt[2] != 0.0 || gt[4] != 0.0) {
    throw InputError(std::string(kDemName) +
                     " is a rotated or sheared grid; warp it north-up first: `gdalwarp DEM "
                     "dem.tif`");
  }
  GeoReference geo;
  const bool southUp = gt[5] > 0.0;
  geo.stepX = gt[1];
  geo.stepY = std::abs(gt[5]);
  geo.originX = gt[0] + 0.5 * gt[1];
  geo.originY = southUp ? gt[3] + (height - 0.5) * gt[5] : gt[3] + 0.5 * gt[5];

  GridSpacing grid;
  if (crs.empty()) {
    // A grid with coordinates but no CRS: metres, as the reader takes them.
    geo.crs = CrsKind::Projected;
  } else {
    // The reader's describeCrs (terrain/io/dem_source.cpp).
    ensureGdal();  // GDAL's messages into gdalLastError, not stderr
    OGRSpatialReference srs;
    srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    CPLErrorReset();
    if (srs.SetFromUserInput(crs.c_str()) != OGRERR_NONE) {
      throw InputError("crs: not a CRS OGR reads (" + gdalLastError() + "): " + crs);
    }
    if (srs.IsGeocentric()) {
      throw InputError(std::string(kDemName) +
                       " has a geocentric CRS; a DEM needs a geographic or projected one");
    }
    if (srs.IsGeographic()) {
      geo.crs = CrsKind::Geographic;
      geo.angularUnitDeg = degrees(srs.GetAngularUnits(nullptr));
      geo.primeMeridianDeg = srs.GetPrimeMeridian(nullptr);
    } else if (srs.IsProjected() || srs.IsLocal()) {
      geo.crs = CrsKind::Projected;
      geo.linearUnitM = srs.GetLinearUnits(nullptr);
    } else {
      throw InputError(
          "crs: neither geographic nor projected, so it gives no cell size: give "
          "cell_size in metres");
    }
    if (srs.IsCompound() || srs.IsVertical()) {
      const double unit = srs.GetTargetLinearUnits("VERT_CS", nullptr);
      if (unit > 0.0 && std::isfinite(unit)) {
        grid.zUnitM = unit;
        grid.zUnitFromCrs = true;
      }
    }
    geo.srs = std::shared_ptr<const OGRSpatialReference>(
        srs.Clone(), [](OGRSpatialReference* copy) { copy->Release(); });
  }
  MetricSpacing m = metricSpacing(kDemName, geo, width, height);
  grid.spacing.x = m.cellSizeXM;
  grid.spacing.y = m.cellSizeYM;
  grid.spacing.rows = std::move(m.rowCellSizeXM);
  if (m.hasCenter) grid.spacing.center = std::array<double, 2>{m.centerLatDeg, m.centerLonDeg};
  return grid;
}

}  // namespace aal::python
