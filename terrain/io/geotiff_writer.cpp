#include "aperture/terrain/io/geotiff_writer.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include <cpl_string.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

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

}  // namespace

void writeGeoTiff(const std::string& path, const RasterImage& image, const GeoReference& geo,
                  const RasterWriteOptions& options) {
  const int width = image.width, height = image.height;
  if (width < 1 || height < 1 || width > kMaxDemSide || height > kMaxDemSide || !image.data ||
      image.bands < 1 || image.bands > 4) {
    throw std::invalid_argument("writeGeoTiff: size must be in [1, " + std::to_string(kMaxDemSide) +
                                "], 1 to 4 bands and data non-null");
  }
  if (geo.crs != CrsKind::None &&
      !(geo.stepX > 0.0 && geo.stepY > 0.0 && std::isfinite(geo.stepX) &&
        std::isfinite(geo.stepY) && std::isfinite(geo.originX) && std::isfinite(geo.originY) &&
        geo.linearUnitM > 0.0)) {
    throw std::invalid_argument("writeGeoTiff: georeference needs finite positive steps");
  }
  const bool bytes = image.type == RasterSampleType::Byte;
  const GDALDataType type = bytes ? GDT_Byte : GDT_Float32;
  const size_t sampleBytes = bytes ? 1 : 4;
  const size_t pixelBytes = sampleBytes * static_cast<size_t>(image.bands);
  ensureGdal();
  AtomicOutput output(path);
  // Absolute: GDAL takes a relative name that starts like a connection
  // string (MEM:::, NUMPY:::) for one (terrain/io/input_file.h).
  const std::string temporary = std::filesystem::absolute(output.temporaryPath()).string();
  try {
    CPLErrorReset();
    CPLStringList creation;
    creation.SetNameValue("COMPRESS", "DEFLATE");
    creation.SetNameValue("BIGTIFF", "IF_SAFER");
    creation.SetNameValue("NUM_THREADS", gdalThreads().c_str());
    // A COG is copied from an in-memory raster (the COG driver cannot Create).
    GDALDriver* driver = GetGDALDriverManager()->GetDriverByName(options.cog ? "MEM" : "GTiff");
    if (driver == nullptr)
      fail(options.cog ? "GDAL has no MEM driver" : "GDAL has no GTiff driver");
    if (!options.cog) {
      creation.SetNameValue("PREDICTOR", bytes ? "2" : "3");
      creation.SetNameValue("TILED", "YES");
      if (image.bands >= 3) {
        creation.SetNameValue("PHOTOMETRIC", "RGB");
        if (image.bands == 4) creation.SetNameValue("ALPHA", "UNASSOCIATED");
      }
    }
    GDALDatasetUniquePtr dataset(driver->Create(options.cog ? "" : temporary.c_str(), width, height,
                                                image.bands, type,
                                                options.cog ? nullptr : creation.List()));
    if (!dataset) fail("cannot create it");
    place(*dataset, geo);
    // The TIFF Software tag: what wrote the file (a COG copies it).
    dataset->SetMetadataItem("TIFFTAG_SOFTWARE", softwareName().c_str());
    for (const auto& [name, value] : options.metadata) {
      dataset->SetMetadataItem(name.c_str(), value.c_str());
    }
    for (int b = 1; b <= image.bands; ++b) {
      GDALRasterBand& band = *dataset->GetRasterBand(b);
      if (options.nodata && band.SetNoDataValue(*options.nodata) != CE_None) {
        fail("cannot set its nodata value");
      }
      if (image.bands >= 3) {
        static constexpr GDALColorInterp kInterp[] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand,
                                                      GCI_AlphaBand};
        band.SetColorInterpretation(kInterp[b - 1]);
      }
    }
    // Bands of rows, so that an interrupt is heard within one band.
    const int bandRows =
        std::max(1, static_cast<int>((size_t{16} << 20) / (pixelBytes * size_t(width))));
    auto* bytesIn = static_cast<GByte*>(const_cast<void*>(image.data));
    for (int row = 0; row < height; row += bandRows) {
      const int rows = std::min(bandRows, height - row);
      if (dataset->RasterIO(GF_Write, 0, row, width, rows,
                            bytesIn + static_cast<size_t>(row) * width * pixelBytes, width, rows,
                            type, image.bands, nullptr, static_cast<GSpacing>(pixelBytes),
                            static_cast<GSpacing>(pixelBytes * width),
                            static_cast<GSpacing>(sampleBytes), nullptr) != CE_None) {
        fail("cannot write its samples");
      }
      throwIfInterrupted();
    }
    if (options.cog) {
      GDALDriver* cog = GetGDALDriverManager()->GetDriverByName("COG");
      if (cog == nullptr) fail("GDAL has no COG driver");
      creation.SetNameValue("PREDICTOR", "YES");
      GDALDatasetUniquePtr copy(cog->CreateCopy(temporary.c_str(), dataset.get(), FALSE,
                                                creation.List(), nullptr, nullptr));
      if (!copy) fail("cannot write it as a COG");
      copy->FlushCache();
      copy.reset();
    } else {
      dataset->FlushCache();
    }
    dataset.reset();
    if (CPLGetLastErrorType() == CE_Failure) fail("GDAL failed");
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
