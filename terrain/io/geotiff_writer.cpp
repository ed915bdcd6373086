#include "aperture/terrain/io/geotiff_writer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/version.h"

namespace aal {

namespace {

// What went wrong and GDAL's last message; writeFloatGeoTiff names the file.
struct GdalWriteError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void fail(const std::string& what) {
  throw GdalWriteError(what + ": " + gdalLastError());
}

// The CRS `geo` names (spatialReferenceOf), else WGS84 for a geographic
// grid, else a local CRS in its linear unit (a grid measured in metres or
// feet with no known CRS).
OGRSpatialReference crsOf(const GeoReference& geo) {
  if (const auto named = spatialReferenceOf(geo)) return *named;
  OGRSpatialReference srs;
  if (geo.crs == CrsKind::Geographic && srs.importFromEPSG(4326) == OGRERR_NONE) return srs;
  srs.Clear();
  srs.SetLocalCS("unnamed");
  srs.SetLinearUnits(geo.linearUnitM == 1.0 ? SRS_UL_METER : "unit", geo.linearUnitM);
  return srs;
}

void place(GDALDataset& dataset, const GeoReference& geo) {
  if (geo.crs == CrsKind::None) return;
  double transform[6] = {geo.originX - 0.5 * geo.stepX, geo.stepX, 0.0,
                         geo.originY + 0.5 * geo.stepY, 0.0,       -geo.stepY};
  const OGRSpatialReference srs = crsOf(geo);
  if (dataset.SetGeoTransform(transform) != CE_None || dataset.SetSpatialRef(&srs) != CE_None) {
    fail("cannot set its georeferencing");
  }
}

// The driver the file is written by: GTiff, or COG (a copy).
const char* driverName(const RasterWriteOptions& options) {
  return options.cog ? "COG" : "GTiff";
}

// Our defaults, then the user's -co KEY=VALUE over them.
CPLStringList creationOptions(const RasterImage& image, const RasterWriteOptions& options) {
  const bool bytes = image.type == RasterSampleType::Byte;
  CPLStringList creation;
  creation.SetNameValue("COMPRESS", "DEFLATE");
  creation.SetNameValue("BIGTIFF", "IF_SAFER");
  creation.SetNameValue("NUM_THREADS", gdalThreads().c_str());
  if (options.cog) {
    creation.SetNameValue("PREDICTOR", "YES");
    creation.SetNameValue("RESAMPLING", "AVERAGE");
  } else {
    creation.SetNameValue("PREDICTOR", bytes ? "2" : "3");
    creation.SetNameValue("TILED", "YES");
    // Float bands (the aperture map's) apart: each band's values are alike,
    // so the predictor and DEFLATE do better band by band (docs/baking.md).
    if (!bytes && image.bands > 1) creation.SetNameValue("INTERLEAVE", "BAND");
    if (bytes && image.bands >= 3) {
      creation.SetNameValue("PHOTOMETRIC", "RGB");
      if (image.bands == 4) creation.SetNameValue("ALPHA", "UNASSOCIATED");
    }
  }
  for (const std::string& option : options.creationOptions) {
    const size_t equals = option.find('=');
    creation.SetNameValue(option.substr(0, equals).c_str(), option.substr(equals + 1).c_str());
  }
  // DEFLATE's fastest level for floats unless the user set one: after the
  // float predictor the low bits of the mantissas are noise that no level
  // squeezes (4096² SVF and visible fraction: 0.4 % larger files, written
  // in 0.80 instead of 1.12 s; docs/performance.md). Bytes keep GDAL's level 6.
  const char* levelKey = options.cog ? "LEVEL" : "ZLEVEL";
  const char* compress = creation.FetchNameValue("COMPRESS");
  if (!bytes && compress && EQUAL(compress, "DEFLATE") && !creation.FetchNameValue(levelKey)) {
    creation.SetNameValue(levelKey, "1");
  }
  return creation;
}

// Nodata, colour interpretation (RGB bytes), description and unit per band.
void describeBands(GDALDataset& dataset, const RasterImage& image,
                   const RasterWriteOptions& options) {
  static constexpr GDALColorInterp kInterp[] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand,
                                                GCI_AlphaBand};
  const bool colour = image.type == RasterSampleType::Byte && image.bands >= 3;
  for (int b = 1; b <= image.bands; ++b) {
    GDALRasterBand& band = *dataset.GetRasterBand(b);
    if (options.nodata && band.SetNoDataValue(*options.nodata) != CE_None) {
      fail("cannot set its nodata value");
    }
    if (colour) band.SetColorInterpretation(kInterp[b - 1]);
    if (static_cast<size_t>(b) <= options.bandLabels.size()) {
      const RasterBandLabel& label = options.bandLabels[b - 1];
      band.SetDescription(label.description.c_str());
      if (!label.unit.empty()) band.SetUnitType(label.unit.c_str());
    }
  }
}

// The samples in bands of rows, so that an interrupt is heard within one.
void writeSamples(GDALDataset& dataset, const RasterImage& image) {
  const bool bytes = image.type == RasterSampleType::Byte;
  const GDALDataType type = bytes ? GDT_Byte : GDT_Float32;
  const size_t sampleBytes = bytes ? 1 : 4;
  const size_t pixelBytes = sampleBytes * static_cast<size_t>(image.bands);
  const int width = image.width;
  const int bandRows =
      std::max(1, static_cast<int>((size_t{16} << 20) / (pixelBytes * size_t(width))));
  auto* bytesIn = static_cast<GByte*>(const_cast<void*>(image.data));
  for (int row = 0; row < image.height; row += bandRows) {
    const int rows = std::min(bandRows, image.height - row);
    if (dataset.RasterIO(GF_Write, 0, row, width, rows,
                         bytesIn + static_cast<size_t>(row) * width * pixelBytes, width, rows, type,
                         image.bands, nullptr, static_cast<GSpacing>(pixelBytes),
                         static_cast<GSpacing>(pixelBytes * width),
                         static_cast<GSpacing>(sampleBytes), nullptr) != CE_None) {
      fail("cannot write its samples");
    }
    throwIfInterrupted();
  }
}

// GDAL's progress callback: stop when the interrupt flag is up.
int continueUnlessInterrupted(double, const char*, void*) {
  return !interruptFlag().load();
}

// Halvings until the smallest overview fits one 256-texel tile (as
// gdaladdo chooses when given no levels), averaged.
void buildOverviews(GDALDataset& dataset, const RasterImage& image) {
  std::vector<int> levels;
  const int side = std::max(image.width, image.height);
  for (int factor = 2; (side + factor / 2 - 1) / (factor / 2) > 256; factor *= 2) {
    levels.push_back(factor);
  }
  if (levels.empty()) return;
  if (dataset.BuildOverviews("AVERAGE", static_cast<int>(levels.size()), levels.data(), 0, nullptr,
                             continueUnlessInterrupted, nullptr) != CE_None) {
    throwIfInterrupted();
    fail("cannot build its overviews");
  }
}

// A COG is copied from an in-memory raster (the COG driver cannot Create).
void copyAsCog(GDALDataset& source, const std::string& temporary, const CPLStringList& creation) {
  GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
  if (cog == nullptr) fail("GDAL has no COG driver");
  GDALDatasetUniquePtr copy(cog->CreateCopy(temporary.c_str(), &source, FALSE, creation.List(),
                                            continueUnlessInterrupted, nullptr));
  throwIfInterrupted();
  if (!copy) fail("cannot write it as a COG");
  copy->FlushCache();
}

void checkImage(const RasterImage& image, const GeoReference& geo) {
  if (image.width < 1 || image.height < 1 || image.width > kMaxDemSide ||
      image.height > kMaxDemSide || !image.data || image.bands < 1 || image.bands > 4) {
    throw std::invalid_argument("writeGeoTiff: size must be in [1, " + std::to_string(kMaxDemSide) +
                                "], 1 to 4 bands and data non-null");
  }
  if (geo.crs != CrsKind::None &&
      !(geo.stepX > 0.0 && geo.stepY > 0.0 && std::isfinite(geo.stepX) &&
        std::isfinite(geo.stepY) && std::isfinite(geo.originX) && std::isfinite(geo.originY) &&
        geo.linearUnitM > 0.0)) {
    throw std::invalid_argument("writeGeoTiff: georeference needs finite positive steps");
  }
}

// The file at `temporary`: created (GTiff) or copied (COG) with `options`.
void writeDataset(const std::string& temporary, const RasterImage& image, const GeoReference& geo,
                  const RasterWriteOptions& options) {
  CPLErrorReset();
  const CPLStringList creation = creationOptions(image, options);
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(options.cog ? "MEM" : "GTiff");
  if (driver == nullptr) fail(options.cog ? "GDAL has no MEM driver" : "GDAL has no GTiff driver");
  const GDALDataType type = image.type == RasterSampleType::Byte ? GDT_Byte : GDT_Float32;
  GDALDatasetUniquePtr dataset(driver->Create(options.cog ? "" : temporary.c_str(), image.width,
                                              image.height, image.bands, type,
                                              options.cog ? nullptr : creation.List()));
  if (!dataset) fail("cannot create it");
  place(*dataset, geo);
  // The TIFF Software tag: what wrote the file (a COG copies it).
  dataset->SetMetadataItem("TIFFTAG_SOFTWARE", softwareName().c_str());
  for (const auto& [name, value] : options.metadata) {
    dataset->SetMetadataItem(name.c_str(), value.c_str());
  }
  describeBands(*dataset, image, options);
  writeSamples(*dataset, image);
  if (options.cog) {
    copyAsCog(*dataset, temporary, creation);
  } else {
    if (options.overviews) buildOverviews(*dataset, image);
    dataset->FlushCache();
  }
  dataset.reset();
  if (CPLGetLastErrorType() == CE_Failure) fail("GDAL failed");
}

// GDAL's warnings, gathered while it validates creation options.
void CPL_STDCALL gatherMessage(CPLErr, CPLErrorNum, const char* message) {
  auto* messages = static_cast<std::vector<std::string>*>(CPLGetErrorHandlerUserData());
  messages->push_back(message);
}

}  // namespace

void checkCreationOptions(const RasterWriteOptions& options) {
  for (const std::string& option : options.creationOptions) {
    const size_t equals = option.find('=');
    if (equals == std::string::npos || equals == 0) {
      throw InputError("-co " + option +
                       ": a creation option is KEY=VALUE, as gdal_translate's (e.g. -co "
                       "COMPRESS=LZW)");
    }
  }
  if (options.creationOptions.empty()) return;
  ensureGdal();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(driverName(options));
  if (driver == nullptr)
    throw InputError(std::string("GDAL has no ") + driverName(options) + " driver");
  CPLStringList given;
  for (const std::string& option : options.creationOptions) {
    const size_t equals = option.find('=');
    given.SetNameValue(option.substr(0, equals).c_str(), option.substr(equals + 1).c_str());
  }
  std::vector<std::string> messages;
  CPLPushErrorHandlerEx(gatherMessage, &messages);
  const int valid = GDALValidateCreationOptions(driver, given.List());
  CPLPopErrorHandler();
  if (valid) return;
  std::string why;
  for (const std::string& m : messages) why += "\n  " + m;
  throw InputError(std::string("-co: GDAL's ") + driverName(options) +
                   " driver refuses the creation options (see `gdalinfo --format " +
                   driverName(options) + "`):" + why);
}

void writeGeoTiff(const std::string& path, const RasterImage& image, const GeoReference& geo,
                  const RasterWriteOptions& options) {
  checkImage(image, geo);
  ensureGdal();
  AtomicOutput output(path);
  // Absolute: GDAL takes a relative name that starts like a connection
  // string (MEM:::, NUMPY:::) for one (terrain/io/input_file.h).
  const std::string temporary = std::filesystem::absolute(output.temporaryPath()).string();
  try {
    writeDataset(temporary, image, geo, options);
  } catch (const GdalWriteError& e) {
    throw output.failure(e.what());
  }
  output.commit();
}

void writeFloatGeoTiff(const std::string& path, int width, int height, const float* data,
                       const GeoReference& geo, const RasterWriteOptions& options) {
  if (width < 1 || height < 1 || width > kMaxDemSide || height > kMaxDemSide || !data) {
    throw std::invalid_argument("writeFloatGeoTiff: size must be in [1, " +
                                std::to_string(kMaxDemSide) + "] and data non-null");
  }
  writeGeoTiff(path, RasterImage{width, height, 1, RasterSampleType::Float32, data}, geo, options);
}

}  // namespace aal
