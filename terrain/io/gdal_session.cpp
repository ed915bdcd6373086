#include "aperture/terrain/io/gdal_session.h"

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <string>
#include <thread>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <gdal_frmts.h>
#include <ogr_spatialref.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/memory_budget.h"

namespace aal {

namespace {

// GDAL's messages are kept for CPLGetLastErrorMsg (our errors quote them).
// A fatal one is an allocation that failed inside GDAL (CPLMalloc, its
// thread-local storage), after which GDAL aborts: said as memory, with
// the limit that applies, and exit 1 instead of SIGABRT.
void handleGdalError(CPLErr kind, CPLErrorNum, const char* message) {
  if (kind != CE_Fatal) return;
  runInterruptCleanup();
  std::fprintf(stderr, "%s: error: GDAL failed (%s): %s\n", program_invocation_short_name,
               message != nullptr ? message : "", outOfMemoryMessage("").c_str());
  std::fflush(stderr);
  std::_Exit(1);
}

void configureGdal() {
  static std::once_flag once;
  std::call_once(once, [] {
    CPLSetErrorHandler(handleGdalError);
    if (CPLGetConfigOption("GDAL_NUM_THREADS", nullptr) == nullptr) {
      CPLSetConfigOption("GDAL_NUM_THREADS", gdalThreads().c_str());
    }
  });
}

}  // namespace

std::string gdalThreads() {
  const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
  const unsigned threads = threadsThatFit(cores);
  return threads >= cores ? "ALL_CPUS" : std::to_string(threads);
}

void ensureGdal() {
  configureGdal();
  static std::once_flag once;
  std::call_once(once, [] { GDALAllRegister(); });
}

GDALDatasetUniquePtr openGeoTiff(const std::string& path) {
  configureGdal();
  static std::once_flag once;
  std::call_once(once, [] { GDALRegister_GTiff(); });
  // GDALOpenEx identifies the file with the allowed drivers only: no second
  // look at the header.
  const char* const geoTiff[] = {"GTiff", nullptr};
  return GDALDatasetUniquePtr(GDALDataset::FromHandle(
      GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, geoTiff, nullptr, nullptr)));
}

std::unique_ptr<OGRSpatialReference> spatialReferenceOf(const GeoReference& geo) {
  configureGdal();  // OGR needs no drivers
  std::unique_ptr<OGRSpatialReference> srs;
  if (geo.srs) {
    srs.reset(geo.srs->Clone());
  } else {
    srs = std::make_unique<OGRSpatialReference>();
    if (geo.epsg <= 0 || srs->importFromEPSG(geo.epsg) != OGRERR_NONE) return nullptr;
  }
  srs->SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  return srs;
}

GDALRasterIOExtraArg interruptibleRead() {
  GDALRasterIOExtraArg extra;
  INIT_RASTERIO_EXTRA_ARG(extra);
  extra.pfnProgress = [](double, const char*, void*) -> int {
    return interruptFlag().load(std::memory_order_relaxed) ? FALSE : TRUE;
  };
  return extra;
}

void throwReadFailure(const std::string& path) {
  throwIfInterrupted();
  if (CPLGetLastErrorNo() == CPLE_OutOfMemory) {
    throw std::runtime_error(path + ": " + outOfMemoryMessage("reading its samples") + " (" +
                             gdalLastError() + ")");
  }
  throw InputError(path + ": cannot read its samples (truncated or corrupt?): " + gdalLastError());
}

std::string gdalLastError(const std::string& fallback) {
  const char* message = CPLGetLastErrorMsg();
  if (message == nullptr || *message == '\0') return fallback;
  return message;
}

}  // namespace aal
