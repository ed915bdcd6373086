#include "aperture/terrain/io/dem_loader.h"

#include <cmath>
#include <cstdio>
#include <iostream>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/georeference.h"
#include "aperture/terrain/io/void_fill.h"

namespace aal {

namespace {

void checkOptions(const DemLoadOptions& options) {
  if (options.cellSizeM &&
      !(*options.cellSizeM >= kMinCellSizeM && *options.cellSizeM <= kMaxCellSizeM)) {
    throw InputError("--cell-size must be a number in [" + std::to_string(kMinCellSizeM) + ", " +
                     std::to_string(kMaxCellSizeM) + "] metres, got " +
                     std::to_string(*options.cellSizeM));
  }
  if (options.zScale && !(*options.zScale > 0.0 && std::isfinite(*options.zScale))) {
    throw InputError("--z-scale must be a positive number, got " + std::to_string(*options.zScale));
  }
  if (!(options.exaggeration > 0.0 && std::isfinite(options.exaggeration))) {
    throw InputError("--exaggeration must be a positive number, got " +
                     std::to_string(options.exaggeration));
  }
}

[[noreturn]] void refuseHeight(const std::string& path, const RawDem& raw, size_t texel,
                               int firstRow, int firstColumn, double zScale) {
  char text[512];
  std::snprintf(text, sizeof text,
                ": height %.6g m (stored %.6g, z scale %.6g) at column %zu, row %zu is beyond any "
                "terrain (|height| <= %.0f m). If it marks missing data, declare it nodata: "
                "`gdal_translate -a_nodata %.9g DEM fixed.tif`; if the heights are in other "
                "units, give --z-scale",
                raw.z[texel] * zScale, double{raw.z[texel]}, zScale,
                texel % static_cast<size_t>(raw.width) + static_cast<size_t>(firstColumn),
                texel / static_cast<size_t>(raw.width) + static_cast<size_t>(firstRow), kMaxHeightM,
                double{raw.z[texel]});
  throw InputError(path + text);
}

void applySpacing(const RawDem& raw, const std::string& path, const DemLoadOptions& options,
                  Heightfield& field) {
  if (raw.geo.crs != CrsKind::None) {
    // Validates the georeferencing even when --cell-size overrides it, and
    // gives the geographic centre.
    MetricSpacing spacing =
        raw.spacing ? *raw.spacing : metricSpacing(path, raw.geo, raw.width, raw.height);
    if (!spacing.scaleNote.empty() && !options.cellSizeM && options.warn) {
      options.warn(path + ": " + spacing.scaleNote);
    }
    field.geo.hasCenter = spacing.hasCenter;
    field.geo.centerLatDeg = spacing.centerLatDeg;
    field.geo.centerLonDeg = spacing.centerLonDeg;
    if (!options.cellSizeM) {
      field.cellSizeXM = spacing.cellSizeXM;
      field.cellSizeYM = spacing.cellSizeYM;
      field.rowCellSizeXM = std::move(spacing.rowCellSizeXM);
      return;
    }
  }
  field.cellSizeXM = field.cellSizeYM = options.cellSizeM.value_or(kDefaultCellSizeM);
}

void warnAboutDefaults(const RawDem& raw, const std::string& path, const DemLoadOptions& options) {
  if (!options.warn) return;
  const bool noCellSize = raw.geo.crs == CrsKind::None && !options.cellSizeM;
  const bool noZScale = raw.geo.crs == CrsKind::None && !raw.zUnitFromFile && !options.zScale;
  if (!noCellSize && !noZScale) return;
  char text[256];
  if (noCellSize && noZScale) {
    std::snprintf(text, sizeof text,
                  "is not georeferenced: assuming %g m cells and heights in metres (z scale "
                  "%g); give --cell-size and --z-scale to set them",
                  kDefaultCellSizeM, kDefaultZScale);
  } else if (noCellSize) {
    std::snprintf(text, sizeof text,
                  "is not georeferenced: assuming %g m cells; give --cell-size to set them",
                  kDefaultCellSizeM);
  } else {
    std::snprintf(text, sizeof text,
                  "is not georeferenced: assuming heights in metres (z scale %g); give "
                  "--z-scale to set it",
                  kDefaultZScale);
  }
  options.warn(path + " " + text);
}

double zScaleOf(const RawDem& raw, const DemLoadOptions& options) {
  return options.zScale.value_or(raw.zUnitFromFile ? raw.zUnitM : kDefaultZScale) *
         options.exaggeration;
}

Heightfield geometryOf(const RawDem& raw, const std::string& path, const DemLoadOptions& options) {
  Heightfield field;
  field.width = raw.width;
  field.height = raw.height;
  field.zScale = zScaleOf(raw, options);
  field.geo = raw.geo;
  field.source = path;
  field.format = raw.format;
  field.driver = raw.driver;
  field.nodata = raw.nodata;
  field.zUnitName = raw.zUnitName;
  applySpacing(raw, path, options, field);
  return field;
}

}  // namespace

// Heights times the z scale; non-finite products become voids, heights
// beyond kMaxHeightM are refused (float horizons lose all precision near
// such spikes: a 1e30 m one gave its neighbours a full sky).
size_t scaleHeights(RawDem& raw, double zScale, const std::string& path, int firstRow,
                    int firstColumn) {
  size_t voids = 0;
  for (size_t i = 0; i < raw.z.size(); ++i) {
    if (!raw.voidMask[i]) {
      const double scaled = raw.z[i] * zScale;
      if (std::isfinite(scaled) && std::isfinite(raw.z[i])) {
        if (!(std::abs(scaled) <= kMaxHeightM))
          refuseHeight(path, raw, i, firstRow, firstColumn, zScale);
        raw.z[i] = static_cast<float>(scaled);
        continue;
      }
      raw.voidMask[i] = 1;
    }
    raw.z[i] = 0.0f;
    ++voids;
  }
  return voids;
}

void warnOnStderr(const std::string& message) {
  std::cerr << "warning: " << message << "\n";
}

Heightfield demGeometry(const DemSource& source, const DemLoadOptions& options) {
  checkOptions(options);
  warnAboutDefaults(source.description(), source.path(), options);
  return geometryOf(source.description(), source.path(), options);
}

HeightWindow readDemRows(const DemSource& source, const Heightfield& geometry, int firstRow,
                         int rows) {
  return readDemWindow(source, geometry, 0, firstRow, source.width(), rows);
}

HeightWindow readDemWindow(const DemSource& source, const Heightfield& geometry, int firstColumn,
                           int firstRow, int columns, int rows) {
  RawDem raw = source.read(firstColumn, firstRow, columns, rows);
  const size_t voids = scaleHeights(raw, geometry.zScale, source.path(), firstRow, firstColumn);
  if (voids > 0) {
    throw InputError(source.path() + ": has voids (" + std::to_string(voids) + " in columns " +
                     std::to_string(firstColumn) + " to " +
                     std::to_string(firstColumn + columns - 1) + " of rows " +
                     std::to_string(firstRow) + " to " + std::to_string(firstRow + rows - 1) +
                     "); a DEM read in parts cannot be filled, since filling needs the whole "
                     "DEM: fill them first, e.g. `gdal_fillnodata.py " +
                     source.path() + " filled.tif`");
  }
  HeightWindow window;
  window.dem = &geometry;
  window.texels = TexelWindow{firstColumn, firstRow, columns, rows};
  window.z = std::move(raw.z);
  return window;
}

Heightfield heightfieldFromRaw(RawDem raw, const std::string& path, const DemLoadOptions& options) {
  checkOptions(options);
  const size_t voids = scaleHeights(raw, zScaleOf(raw, options), path);
  if (voids == raw.texelCount()) {
    throw InputError(path + ": every texel is void (nodata); nothing to use");
  }
  warnAboutDefaults(raw, path, options);

  Heightfield field = geometryOf(raw, path, options);
  field.voidCount = voids;
  if (voids > 0) {
    fillVoidsNearest(raw.z, raw.voidMask, raw.width, raw.height, field.cellSizeXM,
                     field.cellSizeYM);
    field.voidMask = std::move(raw.voidMask);
  }
  field.z = std::move(raw.z);
  return field;
}

Heightfield loadDem(const std::string& path, const DemLoadOptions& options) {
  checkOptions(options);
  return heightfieldFromRaw(DemSource(path, options).readAll(), path, options);
}

}  // namespace aal
