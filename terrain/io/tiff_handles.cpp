#include "tiff_handles.h"

#include <cstdio>
#include <mutex>

#include <geotiff/xtiffio.h>

namespace aal {

namespace {

int onTiffError(TIFF*, void* user, const char* module, const char* fmt, va_list args) {
  static_cast<TiffMessages*>(user)->add(module, fmt, args);
  return 1;  // handled: do not call the global handler (which prints)
}

int onTiffWarning(TIFF*, void*, const char*, const char*, va_list) {
  return 1;
}

struct OptionsFreer {
  void operator()(TIFFOpenOptions* options) const { TIFFOpenOptionsFree(options); }
};

}  // namespace

void TiffMessages::add(const char* module, const char* fmt, va_list args) {
  char text[512];
  std::vsnprintf(text, sizeof text, fmt, args);
  if (!errors.empty()) errors += "; ";
  if (module && *module) errors += std::string(module) + ": ";
  errors += text;
}

TiffHandle openTiff(const std::string& path, const char* mode, TiffMessages& messages) {
  // Registers the GeoTIFF tags with libtiff, so their counts and types are
  // known when a directory is read or written.
  static std::once_flag registered;
  std::call_once(registered, [] { XTIFFInitialize(); });
  std::unique_ptr<TIFFOpenOptions, OptionsFreer> options(TIFFOpenOptionsAlloc());
  TIFFOpenOptionsSetErrorHandlerExtR(options.get(), onTiffError, &messages);
  TIFFOpenOptionsSetWarningHandlerExtR(options.get(), onTiffWarning, &messages);
  return TiffHandle(TIFFOpenExt(path.c_str(), mode, options.get()));
}

}  // namespace aal
