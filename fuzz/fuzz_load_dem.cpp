// libFuzzer target: loadDem as a user calls it, format detection included.
// The first byte picks the file's extension (detection uses content first,
// the extension for .hgt and .asc); the rest is the file.
#include <string>

#include "dem_loader.h"
#include "errors.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".tif", ".hgt", ".asc", ".png", ".exr", ".dat"};
  const std::string path =
      aal::fuzz::scratchPath(std::string("N36W085") + kExtensions[data[0] % 6]);
  aal::fuzz::writeScratch(path, data + 1, size - 1);
  try {
    aal::loadDem(path, aal::fuzz::options());
  } catch (const aal::InputError&) {
  }
  std::remove(path.c_str());
  return 0;
}
