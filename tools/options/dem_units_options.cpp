#include "aperture/tools/options/dem_units_options.h"

#include "aperture/tools/tool_main.h"

namespace aal {

void addDemUnitsOptions(CLI::App& app, DemUnitsOptions& units, bool checked) {
  CLI::Option* cellSize =
      app.add_option("--cell-size", units.cellSizeM,
                     "metres between texel centres; overrides the file's georeferencing");
  CLI::Option* zScale =
      app.add_option("--z-scale", units.zScale,
                     "metres per stored height unit; overrides the file's vertical unit");
  if (checked) {
    cellSize->check(kPositive);
    zScale->check(kPositive);
  }
}

void applyDemUnits(const DemUnitsOptions& units, DemLoadOptions& load) {
  load.cellSizeM = units.cellSizeM;
  load.zScale = units.zScale;
}

}  // namespace aal
