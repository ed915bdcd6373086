// The options aal-bake and aal-bake-mpi share: how the sweep sees the
// terrain and how the tiles are stored. Declared once, so the two tools'
// --help and defaults cannot drift apart (docs/baking.md).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <CLI/CLI.hpp>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/tiled_bake.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/map_compression.h"
#include "aperture/tools/options/dem_units_options.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace aal {

struct SweepCommandLine {
  int azimuths = 64;
  DemUnitsOptions units;
  std::string edge = "open";
  bool curvature = false;
  double refraction = 0.13;
  double maxDistance = 0;
  double nearReach = 0;  // 0: the far field's default (kFarFieldReachCells)
  std::string compression = "rle";
  bool fullFloat = false;
};

// --azimuths, --cell-size, --z-scale, --edge, --curvature, --refraction,
// --max-distance.
inline void addSweepOptions(CLI::App& app, SweepCommandLine& o) {
  app.add_option("--azimuths", o.azimuths, "azimuth slices of the sweep")
      ->check(CLI::Range(4, 4096))
      ->capture_default_str();
  addDemUnitsOptions(app, o.units);
  app.add_option("--edge", o.edge,
                 "beyond the DEM: open sky, or terrain continuing flat at the edge height")
      ->check(CLI::IsMember({"open", "clamp"}))
      ->capture_default_str();
  app.add_flag("--curvature", o.curvature, "drop distant terrain by the Earth's curvature");
  app.add_option("--refraction", o.refraction,
                 "refraction coefficient with --curvature: drop = (1 - k) d^2 / 2R")
      ->check(CLI::Range(0.0, 0.99))
      ->capture_default_str();
  app.add_option("--max-distance", o.maxDistance,
                 "only terrain within this many metres counts (0 = all; the longer the "
                 "limit, the slower: about 1.1x no limit at 10 cells, 1.6x at 100, 2.9x at "
                 "333, 4.2x beyond 500; a tiled bake without it takes its far horizons from a "
                 "pyramid)")
      ->check(kNonNegative);
}

// --near-reach (tiled bakes without --max-distance).
inline void addNearReachOption(CLI::App& app, SweepCommandLine& o) {
  app.add_option("--near-reach", o.nearReach,
                 "tiled, without --max-distance: metres the near sweep covers before the far "
                 "field's pyramid takes over (default 128 cells of the DEM's smallest cell, "
                 "minimum 16, where the pyramid's blocks are one cell; each doubling divides "
                 "the pyramid's size by 4 and adds that many steps to every tile's lines)")
      ->check(kPositive);
}

// --compression, --float.
inline void addMapStorageOptions(CLI::App& app, SweepCommandLine& o) {
  app.add_option("--compression", o.compression,
                 "the maps' EXR compression: rle (fast), zip (~25 % smaller, ~5x slower to "
                 "write), none")
      ->check(CLI::IsMember({"rle", "zip", "none"}))
      ->capture_default_str();
  app.add_flag("--float", o.fullFloat, "store 32-bit floats instead of 16-bit halves");
}

// InputError when the options contradict each other.
inline void checkSweepOptions(const SweepCommandLine& o) {
  if (o.nearReach > 0 && o.maxDistance > 0) {
    throw InputError("--near-reach is the far field's, which --max-distance leaves out");
  }
}

// The files a tiled bake writes into its folder, by name (docs/baking.md,
// "The tile folder").
inline OutputFamily tileFolderFiles(const std::string& folder) {
  return {"-o", folder, folder, std::string("the tiled bake's files (") + kTiledBakeFileNames + ")",
          isTiledBakeFileName};
}

// InputError unless `folder` can be a tiled bake's output (-o): an existing
// writable folder, or a new one in an existing writable folder, whose files
// of the bake's names are writable files, none of them one of `inputs` (a
// DEM named svf_0000_0000.tif in it, or a VRT's source there), and the
// folder none of `otherOutputs`.
inline void checkTiledBakeOutput(const NamedPaths& inputs, const std::string& folder,
                                 const NamedPaths& otherOutputs = {}) {
  namespace fs = std::filesystem;
  NamedPaths outputs = {{"-o", folder}};
  append(outputs, otherOutputs);
  checkDistinctFiles(inputs, outputs, {tileFolderFiles(folder)});
  std::error_code error;
  if (fs::exists(folder, error) && !fs::is_directory(folder, error)) {
    throw InputError("a tiled bake writes a folder: " + folder + " is a file");
  }
  if (fs::is_directory(folder, error)) {
    requireWritableFamily(tileFolderFiles(folder), "index.txt");
  } else {
    requireWritableOutput(folder);  // its parent folder exists and is writable
  }
}

// `windowed`: the bake reads the DEM in windows (a tiled bake that may, or
// --low-memory): a read that does not fit says what helps then, not to use
// --low-memory again.
inline DemLoadOptions demLoadOptions(const SweepCommandLine& o, bool windowed) {
  DemLoadOptions load;
  if (windowed) {
    load.memoryHint =
        "a tiled bake reads the DEM in windows already (a tile and its halo, and rows of up to "
        "64 MB for its checksum): give a smaller --tile-size (or a shorter --max-distance), or "
        "allow more memory (AAL_MEMORY_LIMIT)";
  }
  applyDemUnits(o.units, load);
  return load;
}

// The sweep's part of BakeOptions; the rest keeps `bake`'s values.
inline void applySweepOptions(const SweepCommandLine& o, BakeOptions& bake) {
  bake.azimuths = o.azimuths;
  bake.clampEdge = o.edge == "clamp";
  bake.curvature = o.curvature;
  bake.refraction = o.refraction;
  bake.maxDistanceM = o.maxDistance;
}

inline MapCompression mapCompression(const SweepCommandLine& o) {
  return o.compression == "zip"    ? MapCompression::Zip
         : o.compression == "none" ? MapCompression::None
                                   : MapCompression::Rle;
}

}  // namespace aal
