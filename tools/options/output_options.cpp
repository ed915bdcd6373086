#include "aperture/tools/options/output_options.h"

#include <cstdio>
#include <vector>

namespace aal {

void addQuietFlag(CLI::App& app, bool& quiet, bool progress) {
  app.add_flag("-q,--quiet", quiet, progress ? "no progress and no summary" : "no summary");
}

ProgressStyle ProgressOptions::style() const {
  if (progress.empty()) return quiet ? ProgressStyle::None : ProgressStyle::Bar;
  return parseProgressStyle(progress).value_or(ProgressStyle::Bar);
}

void addProgressOptions(CLI::App& app, ProgressOptions& o) {
  addQuietFlag(app, o.quiet);
  const std::vector<std::string> names(std::begin(kProgressStyleNames),
                                       std::end(kProgressStyleNames));
  app.add_option("--progress", o.progress,
                 "how progress is shown: bar (on stderr, the default; none with -q), gdal "
                 "(GDAL's 0...10...100 - done. on stdout), json (one line per report on stdout: "
                 "{\"stage\":\"baking\",\"done\":N,\"total\":M,\"seconds\":S}; other stdout text "
                 "goes to stderr), none; docs/cli.md")
      ->check(CLI::IsMember(names));
}

FILE* textOutput(ProgressStyle style) {
  return style == ProgressStyle::Json ? stderr : stdout;
}

}  // namespace aal
