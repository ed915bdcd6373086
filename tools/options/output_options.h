// What a tool tells while it works: -q/--quiet and --progress (aal-render,
// aal-relief, aal-bake; aal-bake-mpi takes -q only). Each tool's -o names a
// different kind of file, so it stays with the tool.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "aperture/preprocess/progress_reporter.h"

namespace aal {

// -q, --quiet: no progress bars (`progress`: the tool shows them; aal-bake-mpi
// does not) and no closing summary on stderr.
void addQuietFlag(CLI::App& app, bool& quiet, bool progress = true);

struct ProgressOptions {
  bool quiet = false;
  std::string progress;  // --progress; empty: bar, or none with -q

  // --progress when given, else none with -q and a bar without.
  ProgressStyle style() const;
};

// -q and --progress bar|gdal|json|none (docs/cli.md, "Progress for scripts").
void addProgressOptions(CLI::App& app, ProgressOptions& o);

// Where a tool prints what it prints on stdout besides progress (tables,
// --stats): stderr when --progress json keeps stdout for its lines.
FILE* textOutput(ProgressStyle style);

}  // namespace aal
