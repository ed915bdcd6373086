// Refusing a command line whose outputs would overwrite its inputs or each
// other (issue 17: `aal-bake d.tif -o d.tif` turned the DEM into an aperture
// map and exited 0). Checked before any work, for every tool.
#pragma once

#include <filesystem>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "aperture/terrain/errors.h"

namespace aal {

// (option, path) pairs; empty paths are ignored.
using NamedPaths = std::vector<std::pair<std::string, std::string>>;

// Whether two paths name one file: the same path once made absolute and
// normal (symbolic links resolved as far as they exist), or the same inode
// (hard links) when both exist.
inline bool sameFile(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (fs::exists(a, error) && fs::exists(b, error) && fs::equivalent(a, b, error)) return true;
  const fs::path ca = fs::weakly_canonical(fs::absolute(a, error), error);
  const fs::path cb = fs::weakly_canonical(fs::absolute(b, error), error);
  return !ca.empty() && ca == cb;
}

// Throws InputError naming both options when an output is an input or
// another output.
inline void checkDistinctFiles(const NamedPaths& inputs, const NamedPaths& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const auto& [outName, outPath] = outputs[i];
    if (outPath.empty()) continue;
    for (const auto& [inName, inPath] : inputs) {
      if (!inPath.empty() && sameFile(outPath, inPath)) {
        throw InputError(outName + " " + outPath + " is the input " + inName + " (" + inPath +
                         "): writing it would destroy it; choose another output");
      }
    }
    for (size_t j = 0; j < i; ++j) {
      const auto& [otherName, otherPath] = outputs[j];
      if (!otherPath.empty() && sameFile(outPath, otherPath)) {
        throw InputError(outName + " " + outPath + " is also the output of " + otherName +
                         ": give each output its own file");
      }
    }
  }
}

}  // namespace aal
