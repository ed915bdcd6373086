// libFuzzer target: loadDem as a user calls it, on any bytes. The first
// byte picks the file name (GDAL's SRTMHGT and AAIGrid drivers look at
// it); the rest is the file, opened from GDAL's in-memory files.
#include <cmath>
#include <cstdlib>
#include <string>

#include "aperture/fuzz/fuzz_common.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  aal::fuzz::initGdal();
  static const char* const kExtensions[] = {".tif", ".hgt", ".asc", ".png"};
  const aal::fuzz::MemoryFile file(std::string("N36W085") + kExtensions[data[0] % 4], data + 1,
                                   size - 1);
  try {
    const aal::Heightfield f = aal::loadDem(file.path(), aal::fuzz::options());
    // What every caller relies on: finite heights, a mask of the right size.
    for (const float z : f.z) {
      if (!std::isfinite(z)) std::abort();
    }
    if (f.z.size() != f.texelCount() || (!f.voidMask.empty() && f.voidMask.size() != f.z.size())) {
      std::abort();
    }
  } catch (const aal::InputError&) {
  }
  return 0;
}
