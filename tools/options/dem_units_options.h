// A DEM's units on a tool's command line: --cell-size and --z-scale, which
// override what the file says (or assumes without georeferencing).
#pragma once

#include <optional>

#include <CLI/CLI.hpp>

#include "aperture/terrain/io/dem_options.h"

namespace aal {

struct DemUnitsOptions {
  std::optional<double> cellSizeM;  // --cell-size
  std::optional<double> zScale;     // --z-scale
};

// --cell-size and --z-scale. `checked`: refused by the parser unless
// positive; aal-info leaves them to loadDem's checks (its messages).
void addDemUnitsOptions(CLI::App& app, DemUnitsOptions& units, bool checked = true);

// The options' values in `load`.
void applyDemUnits(const DemUnitsOptions& units, DemLoadOptions& load);

}  // namespace aal
