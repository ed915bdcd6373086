#include "gdal_session.h"

#include <mutex>

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

namespace aal {

void ensureGdal() {
  static std::once_flag once;
  std::call_once(once, [] {
    GDALAllRegister();
    CPLSetErrorHandler(CPLQuietErrorHandler);
    if (CPLGetConfigOption("GDAL_NUM_THREADS", nullptr) == nullptr) {
      CPLSetConfigOption("GDAL_NUM_THREADS", "ALL_CPUS");
    }
  });
}

std::string gdalLastError(const std::string& fallback) {
  const char* message = CPLGetLastErrorMsg();
  if (message == nullptr || *message == '\0') return fallback;
  return message;
}

}  // namespace aal
