#include "aperture/tools/options/output_options.h"

namespace aal {

void addQuietFlag(CLI::App& app, bool& quiet, bool progress) {
  app.add_flag("-q,--quiet", quiet, progress ? "no progress and no summary" : "no summary");
}

}  // namespace aal
