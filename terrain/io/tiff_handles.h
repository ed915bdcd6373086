// Owning handles for libtiff and libgeotiff objects, and opening a TIFF with
// its messages collected instead of printed; shared by the GeoTIFF reader
// and writer.
#pragma once

#include <cstdarg>
#include <memory>
#include <string>

#include <geotiff/geotiff.h>
#include <tiffio.h>

namespace aal {

struct TiffCloser {
  void operator()(TIFF* tif) const { TIFFClose(tif); }
};
struct GtifFreer {
  void operator()(GTIF* gtif) const { GTIFFree(gtif); }
};

using TiffHandle = std::unique_ptr<TIFF, TiffCloser>;
using GtifHandle = std::unique_ptr<GTIF, GtifFreer>;

// libtiff and libgeotiff errors of one open file, kept for the user's message.
struct TiffMessages {
  std::string errors;
  void add(const char* module, const char* fmt, va_list args);
};

// Opens `path` with libtiff `mode` ("r", "w", "w8"), with the GeoTIFF tags
// registered and errors collected in `messages` (warnings are dropped:
// unknown tags and the like are nothing a user needs to see). Null on failure.
TiffHandle openTiff(const std::string& path, const char* mode, TiffMessages& messages);

}  // namespace aal
