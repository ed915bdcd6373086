// Owning handles for libtiff and libgeotiff objects, shared by the GeoTIFF
// reader and writer.
#pragma once

#include <memory>

#include <geotiff/geotiff.h>
#include <tiffio.h>

namespace aal {

struct TiffCloser {
  void operator()(TIFF* tif) const { TIFFClose(tif); }
};
struct GtifFreer {
  void operator()(GTIF* gtif) const { GTIFFree(gtif); }
};
struct TiffOptionsFreer {
  void operator()(TIFFOpenOptions* options) const { TIFFOpenOptionsFree(options); }
};

using TiffHandle = std::unique_ptr<TIFF, TiffCloser>;
using GtifHandle = std::unique_ptr<GTIF, GtifFreer>;
using TiffOptionsHandle = std::unique_ptr<TIFFOpenOptions, TiffOptionsFreer>;

}  // namespace aal
