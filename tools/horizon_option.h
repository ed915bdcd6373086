// --horizons FILE and the horizon shading mode, as aal-render and aal-view
// take them: the directional horizons of aal-bake --horizons (docs/baking.md,
// "Directional horizons"), checked against the DEM before anything is drawn.
#pragma once

#include <cstdio>
#include <map>
#include <string>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/heightfield_checksum.h"
#include "aperture/terrain/io/horizon_map.h"
#include "aperture/terrain/light/shading.h"

namespace aal {

// The shading modes of every tool and the horizon mode, which needs the
// DEM's directional horizons.
inline const std::map<std::string, ShadingMode>& toolShadingModes() {
  static const std::map<std::string, ShadingMode> modes = [] {
    std::map<std::string, ShadingMode> m = shadingModeNames();
    m.emplace("horizon", ShadingMode::Horizon);
    return m;
  }();
  return modes;
}

// The horizon map at `path`, which must be of `field`: InputError naming
// the file when it cannot be read, is not a horizon map, has another size or
// was baked from other heights (its checksum, as the aperture map's). Files
// from before the checksum (versions 1 and 2) are checked by size alone,
// with a note saying so.
inline HorizonMap readHorizonsOfDem(const std::string& path, const Heightfield& field) {
  HorizonMap horizons;
  try {
    horizons = readHorizonMap(path);
  } catch (const std::runtime_error& e) {
    throw InputError(std::string("--horizons: ") + e.what());
  }
  if (horizons.width != field.width || horizons.height != field.height) {
    throw InputError("--horizons " + path + " is " + std::to_string(horizons.width) + "x" +
                     std::to_string(horizons.height) + ", the DEM " + std::to_string(field.width) +
                     "x" + std::to_string(field.height) +
                     ": bake them from this DEM (aal-bake DEM --horizons FILE)");
  }
  if (horizons.sourceChecksum.empty()) {
    std::fprintf(stderr,
                 "note: --horizons %s predates the heights checksum: only its size is checked "
                 "against the DEM\n",
                 path.c_str());
  } else if (!heightfieldMatchesChecksum(field, horizons.sourceChecksum)) {
    throw InputError("--horizons " + path + " was baked from other heights than this DEM's (" +
                     horizons.sourceChecksum + ", the DEM " + heightfieldChecksum(field) +
                     "; the z scale or --exaggeration counts): bake them from this DEM "
                     "(aal-bake DEM --horizons FILE)");
  }
  return horizons;
}

}  // namespace aal
