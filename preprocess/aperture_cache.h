// A cache of baked aperture maps, so that tools which need one (aal-render,
// aal-view) bake a DEM only once. Maps live in $AAL_CACHE_DIR, else
// $XDG_CACHE_HOME/aperture, else ~/.cache/aperture, named by the heights'
// checksum and the bake options.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/progress_reporter.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/horizon_map.h"

namespace aal {

std::filesystem::path apertureCacheDirectory();

// Cache file for this DEM (its loaded heights) and these bake options.
std::filesystem::path cachedAperturePath(const Heightfield& field, const BakeOptions& options);

// The cache entry for this DEM and these options when it exists, matches
// the DEM and verifies: every pixel decodes and matches aal:pixelChecksum
// (an entry without one is not verified). Else empty, with the reason in
// *whyUnusable for an entry that exists. Reads the whole map.
std::filesystem::path findCachedAperture(const Heightfield& field, const std::string& demPath,
                                         const BakeOptions& options,
                                         std::string* whyUnusable = nullptr);

// Where the directional horizons of a cache entry baked with
// options.horizons lie: beside it, named by its name, the directions and
// the code bits.
std::filesystem::path cachedHorizonsPath(const Heightfield& field, const BakeOptions& options);

// The cached horizons for this DEM and these options when they exist and
// are of this DEM's size; else an empty map (width 0).
HorizonMap findCachedHorizons(const Heightfield& field, const BakeOptions& options);

// An aperture map for a DEM: the path of a valid cache entry, or the map in
// memory when the cache cannot be written.
struct CachedAperture {
  std::filesystem::path path;  // empty when not cached
  ApertureMap map;             // filled only when not cached
  // With options.horizons: the bake's directional horizons (cached beside
  // the map too), or a cache hit's (findCachedHorizons; empty when the entry
  // was baked without them).
  HorizonMap horizons;
};

// The cached map when present and verified (findCachedAperture), else a
// fresh bake (its progress in the `progress` style, stage "baking"; `quiet`: no notes) written to
// the cache atomically (with options.horizons, the horizons beside it); an unusable entry is
// replaced, with a warning line on stderr naming it and why. `demPath` names the DEM in the map's
// aal:source. options.progress, when set, is called too; options.cancel stops the bake
// (BakeCancelled) before anything is written. An entry that would be written over the DEM or one of
// `inputs` (the run's other input files: AAL_CACHE_DIR pointed at their folder) is not written: the
// map stays in memory, with a warning.
CachedAperture cachedOrBakedAperture(const Heightfield& field, const std::string& demPath,
                                     BakeOptions options, ProgressStyle progress, bool quiet,
                                     const std::vector<std::string>& inputs = {});
// The same with progress as a bar on stderr, or none when quiet.
inline CachedAperture cachedOrBakedAperture(const Heightfield& field, const std::string& demPath,
                                            BakeOptions options, bool quiet,
                                            const std::vector<std::string>& inputs = {}) {
  return cachedOrBakedAperture(field, demPath, std::move(options),
                               quiet ? ProgressStyle::None : ProgressStyle::Bar, quiet, inputs);
}

}  // namespace aal
