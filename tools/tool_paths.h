// Refusing a command line whose outputs would overwrite its inputs or each
// other (`aal-bake d.tif -o d.tif` turned the DEM into an aperture map and
// exited 0). Checked before any work, for every tool, against every path a
// run writes: the ones given and the ones it derives (a sequence's frames,
// a comparison's images, a tiled bake's files), and every file an input is
// made of (a VRT's sources, a tiled map's tiles). docs/dem-input.md,
// "Outputs".
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/raster_files.h"
#include "aperture/tools/tool_options.h"

namespace aal {

// A path of a run: the option that names it, the path and, for a path the
// run derives from another (a VRT's source, a sequence's frame), what it
// is in words ("a file GDAL reads for d.vrt", "frame 1 of -o out.png").
struct RunPath {
  RunPath(std::string optionName, std::string pathName, std::string what = {})
      : option(std::move(optionName)), path(std::move(pathName)), note(std::move(what)) {}
  std::string option, path, note;
};
// Empty paths are ignored.
using NamedPaths = std::vector<RunPath>;

// Files a run writes into `folder` by name, as many as the input asks for
// (a tiled bake's tiles, a sequence's frames): `writes` says whether a file
// name is one of them, `what` names them in messages ("the tiled bake's
// files (tile_ROW_COL.exr, ...)").
struct OutputFamily {
  std::string option;  // the output option they come from, e.g. "-o"
  std::string given;   // its value, e.g. "out.png" or the tile folder
  std::string folder;
  std::string what;
  std::function<bool(const std::string& name)> writes;
};

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

// The entries (folder, name) a write of `path` could replace: the path as
// given and where its links lead, each folder with its links resolved.
inline std::vector<std::pair<std::filesystem::path, std::string>> entriesOf(
    const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path absolute = fs::absolute(path, error).lexically_normal();
  std::vector<std::pair<fs::path, std::string>> entries;
  for (const fs::path& p : {absolute, fs::weakly_canonical(absolute, error)}) {
    if (p.empty() || !p.has_filename()) continue;
    entries.emplace_back(fs::weakly_canonical(p.parent_path(), error), p.filename().string());
  }
  return entries;
}

// Whether `path` (or where its links lead) is a file of `family`.
inline bool inFamily(const std::string& path, const OutputFamily& family) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::path folder = fs::weakly_canonical(fs::absolute(family.folder, error), error);
  for (const auto& [parent, name] : entriesOf(path)) {
    if (parent == folder && family.writes(name)) return true;
  }
  return false;
}

// `option`'s input `path` with the files it is made of: a raster's files as
// GDAL reads them (rasterFiles: its sidecars, a VRT's sources), a folder's
// files (a tiled aperture map's tiles, index and mosaic). Writing any of
// them would change the input.
inline NamedPaths inputFiles(const std::string& option, const std::string& path,
                             bool raster = false) {
  namespace fs = std::filesystem;
  NamedPaths files{{option, path}};
  if (path.empty()) return files;
  std::error_code error;
  if (fs::is_directory(path, error)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(path, error)) {
      if (entry.is_regular_file(error)) {
        files.push_back({option, entry.path().string(), "a file of the folder " + path});
      }
    }
  } else if (raster) {
    for (const std::string& file : rasterFiles(path)) {
      if (!sameFile(file, path)) files.push_back({option, file, "a file GDAL reads for " + path});
    }
  }
  return files;
}

inline void append(NamedPaths& to, const NamedPaths& more) {
  to.insert(to.end(), more.begin(), more.end());
}

namespace detail {

inline std::string describeOutput(const RunPath& p) {
  return p.note.empty() ? p.option + " " + p.path : p.path + " (" + p.note + ")";
}
inline std::string describeInput(const RunPath& p) {
  return "the input " + p.option + " (" + p.path + (p.note.empty() ? "" : ", " + p.note) + ")";
}
// "-o out.png writes the frames ... into DIR": where a family goes.
inline std::string describeFamily(const OutputFamily& f) {
  return f.option + " " + f.given + " writes " + f.what + " into " +
         (f.given == f.folder ? std::string("it") : f.folder);
}

// The folders a run writes into: a write there removes the temporaries of
// dead processes (removeDeadTemporaries).
inline std::vector<std::pair<std::string, std::string>> outputFolders(
    const NamedPaths& outputs, const std::vector<OutputFamily>& families) {
  namespace fs = std::filesystem;
  std::vector<std::pair<std::string, std::string>> folders;  // (option, folder)
  for (const RunPath& out : outputs) {
    if (out.path.empty()) continue;
    const fs::path parent = fs::path(out.path).parent_path();
    folders.emplace_back(out.option, parent.empty() ? "." : parent.string());
  }
  for (const OutputFamily& family : families) folders.emplace_back(family.option, family.folder);
  return folders;
}

}  // namespace detail

// Throws InputError naming both when an output is an input or another
// output, when an input is one of the files a family writes, or when an
// input in an output's folder is named like a temporary file (which a
// write there may remove).
inline void checkDistinctFiles(const NamedPaths& inputs, const NamedPaths& outputs,
                               const std::vector<OutputFamily>& families = {}) {
  namespace fs = std::filesystem;
  for (size_t i = 0; i < outputs.size(); ++i) {
    const RunPath& out = outputs[i];
    if (out.path.empty()) continue;
    for (const RunPath& in : inputs) {
      if (!in.path.empty() && sameFile(out.path, in.path)) {
        throw InputError(detail::describeOutput(out) + " is " + detail::describeInput(in) +
                         ": writing it would destroy it; choose another output");
      }
    }
    for (size_t j = 0; j < i; ++j) {
      const RunPath& other = outputs[j];
      if (!other.path.empty() && sameFile(out.path, other.path)) {
        throw InputError(detail::describeOutput(out) + " is also the output of " +
                         detail::describeOutput(other) + ": give each output its own file");
      }
    }
    for (const OutputFamily& family : families) {
      if (inFamily(out.path, family)) {
        throw InputError(detail::describeFamily(family) + ", and " + detail::describeOutput(out) +
                         " is one of them: give each output its own file");
      }
    }
  }
  for (const OutputFamily& family : families) {
    for (const RunPath& in : inputs) {
      if (!in.path.empty() && inFamily(in.path, family)) {
        throw InputError(detail::describeFamily(family) + ", and " + detail::describeInput(in) +
                         " is one of them: writing it would destroy it; move the input or "
                         "choose another output");
      }
    }
  }
  for (const auto& [option, folder] : detail::outputFolders(outputs, families)) {
    std::error_code error;
    const fs::path canonical = fs::weakly_canonical(fs::absolute(folder, error), error);
    for (const RunPath& in : inputs) {
      if (in.path.empty()) continue;
      for (const auto& [parent, name] : entriesOf(in.path)) {
        if (parent == canonical && isTemporaryName(name)) {
          throw InputError(detail::describeInput(in) + " is named like a temporary file (" +
                           ".NAME.tmp-PID-N), which a write into its folder (" + option + " " +
                           folder + ") removes once process PID is gone: rename the input");
        }
      }
    }
  }
}

// requireWritableOutput for every existing file of `family` (a device, FIFO
// or folder of such a name is refused before any work, not half way) and
// for a new one in its folder when that exists.
inline void requireWritableFamily(const OutputFamily& family, const std::string& example) {
  namespace fs = std::filesystem;
  std::error_code error;
  if (!fs::is_directory(family.folder, error)) return;
  requireWritableOutput((fs::path(family.folder) / example).string());
  for (const fs::directory_entry& entry : fs::directory_iterator(family.folder, error)) {
    if (family.writes(entry.path().filename().string())) {
      requireWritableOutput(entry.path().string());
    }
  }
}

}  // namespace aal
