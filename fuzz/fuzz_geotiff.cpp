// libFuzzer target: GeoTIFF/TIFF reader (libtiff tags + OpenImageIO pixels)
// and the rest of loading. Any exception but InputError is a bug.
#include "dem_loader.h"
#include "errors.h"
#include "fuzz_common.h"
#include "geotiff_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path = aal::fuzz::scratchPath("input.tif");
  aal::fuzz::writeScratch(path, data, size);
  const aal::DemLoadOptions options = aal::fuzz::options();
  try {
    aal::heightfieldFromRaw(aal::readGeoTiff(path, options), path, options);
  } catch (const aal::InputError&) {
  }
  return 0;
}
