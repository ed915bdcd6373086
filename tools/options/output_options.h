// What a tool tells while it works: -q/--quiet (aal-render, aal-relief,
// aal-bake, aal-bake-mpi). Each tool's -o names a different kind of file,
// so it stays with the tool.
#pragma once

#include <CLI/CLI.hpp>

namespace aal {

// -q, --quiet: no progress bars (`progress`: the tool shows them; aal-bake-mpi
// does not) and no closing summary on stderr.
void addQuietFlag(CLI::App& app, bool& quiet, bool progress = true);

}  // namespace aal
