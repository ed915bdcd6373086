// Test rasters made with GDAL's own API (no committed binaries): a raster
// is described in memory, then written by the driver a user's tool would
// have used, with its creation options.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>
#include <vector>

#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "aperture/terrain/io/gdal_session.h"

namespace aal::test {

struct GdalRaster {
  int width = 4, height = 3, bands = 1;
  GDALDataType type = GDT_Float32;
  // value(band, column, row), band from 1
  std::function<double(int, int, int)> value = [](int, int c, int r) { return 10.0 * r + c; };
  bool hasTransform = false;
  double transform[6] = {0, 1, 0, 0, 0, -1};
  std::string crs;                           // anything OGRSpatialReference::SetFromUserInput takes
  std::vector<std::string> creationOptions;  // "NAME=VALUE"
  std::function<void(GDALDataset&)> extra;   // nodata, scale, colour tables, masks ...
};

// Builds the raster in GDAL's MEM driver, then CreateCopy's it with
// `driver` to `path` (so every driver that can copy, PNG and COG included,
// works the same). Returns false with a test failure when GDAL refuses.
inline bool writeGdalRaster(const std::string& path, const GdalRaster& r,
                            const std::string& driver = "GTiff") {
  ensureGdal();
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDatasetUniquePtr ds(mem->Create("", r.width, r.height, r.bands, r.type, nullptr));
  if (!ds) {
    ADD_FAILURE() << "MEM create: " << CPLGetLastErrorMsg();
    return false;
  }
  if (r.hasTransform) ds->SetGeoTransform(const_cast<double*>(r.transform));
  if (!r.crs.empty()) {
    OGRSpatialReference srs;
    if (srs.SetFromUserInput(r.crs.c_str()) != OGRERR_NONE) {
      ADD_FAILURE() << "bad CRS " << r.crs;
      return false;
    }
    ds->SetSpatialRef(&srs);
  }
  for (int b = 1; b <= r.bands; ++b) {
    std::vector<double> values(static_cast<size_t>(r.width) * r.height);
    for (int y = 0; y < r.height; ++y) {
      for (int x = 0; x < r.width; ++x)
        values[static_cast<size_t>(y) * r.width + x] = r.value(b, x, y);
    }
    if (ds->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, r.width, r.height, values.data(), r.width,
                                       r.height, GDT_Float64, 0, 0, nullptr) != CE_None) {
      ADD_FAILURE() << "MEM write: " << CPLGetLastErrorMsg();
      return false;
    }
  }
  if (r.extra) r.extra(*ds);
  CPLStringList options;
  for (const std::string& o : r.creationOptions) options.AddString(o.c_str());
  GDALDriver* out = GetGDALDriverManager()->GetDriverByName(driver.c_str());
  if (out == nullptr) {
    ADD_FAILURE() << "no GDAL driver " << driver;
    return false;
  }
  GDALDatasetUniquePtr copy(
      out->CreateCopy(path.c_str(), ds.get(), FALSE, options.List(), nullptr, nullptr));
  if (!copy) {
    ADD_FAILURE() << driver << " CreateCopy: " << CPLGetLastErrorMsg();
    return false;
  }
  return true;
}

// GDAL's own statistics of band 1 (exact, honouring nodata and masks).
struct GdalStatistics {
  double min = 0, max = 0, mean = 0;
};
inline GdalStatistics gdalStatistics(const std::string& path) {
  ensureGdal();
  GDALDatasetUniquePtr ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  GdalStatistics s;
  double sd = 0;
  if (!ds) {
    ADD_FAILURE() << "cannot open " << path;
    return s;
  }
  GDALRasterBand* band = ds->GetRasterBand(1);
  if (band->ComputeStatistics(FALSE, &s.min, &s.max, &s.mean, &sd, nullptr, nullptr) != CE_None) {
    ADD_FAILURE() << "statistics of " << path << ": " << CPLGetLastErrorMsg();
  }
  int ok = 0;
  const double scale = band->GetScale(&ok), offset = band->GetOffset(&ok);
  s.min = s.min * scale + offset;
  s.max = s.max * scale + offset;
  s.mean = s.mean * scale + offset;
  return s;
}

}  // namespace aal::test
