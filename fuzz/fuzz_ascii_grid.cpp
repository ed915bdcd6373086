// libFuzzer target: ESRI ASCII grid parser. The input is the grid text; a NUL
// byte separates it from the text of a .prj sidecar.
#include <optional>
#include <string>
#include <string_view>

#include "ascii_grid_reader.h"
#include "dem_loader.h"
#include "errors.h"
#include "fuzz_common.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  const size_t nul = input.find('\0');
  const std::string_view grid = input.substr(0, nul);
  const std::optional<std::string> prj = nul == std::string_view::npos
                                             ? std::nullopt
                                             : std::optional<std::string>(input.substr(nul + 1));
  const aal::DemLoadOptions options = aal::fuzz::options();
  try {
    aal::heightfieldFromRaw(aal::parseAsciiGrid("fuzz.asc", grid, prj, options), "fuzz.asc",
                            options);
  } catch (const aal::InputError&) {
  }
  return 0;
}
