#include "aperture/preprocess/aperture_cache.h"

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "aperture/preprocess/progress_reporter.h"
#include "aperture/terrain/errors.h"

namespace aal {

namespace fs = std::filesystem;

fs::path apertureCacheDirectory() {
  if (const char* dir = std::getenv("AAL_CACHE_DIR"); dir && *dir) return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return fs::path(xdg) / "aperture";
  if (const char* home = std::getenv("HOME"); home && *home) {
    return fs::path(home) / ".cache" / "aperture";
  }
  return fs::temp_directory_path() / "aperture-cache";
}

namespace {

// The cache file's name: the heights' checksum, then the options. The
// checksum does not see the cell size: the name carries it.
std::string cacheName(const std::string& checksum, const Heightfield& field, const BakeOptions& o) {
  char options[160];
  std::snprintf(options, sizeof options, "-s%.9gx%.9g-%s-a%d-r%d-%s-c%d-k%.3f-d%.0f.exr",
                field.cellSizeXM, field.cellSizeYM,
                o.method == BakeMethod::Sweep ? "sweep" : "rays", o.azimuths, o.rays,
                o.clampEdge ? "clamp" : "open", o.curvature ? 1 : 0, o.refraction, o.maxDistanceM);
  return checksum + options;
}

// The entry an older cache holds for this DEM: named by the version 1
// heights checksum (heightfield_checksum.h), which is computed only when the
// folder holds a name of that form with these options.
fs::path legacyCachedAperture(const Heightfield& field, const BakeOptions& o) {
  const std::string options = cacheName("", field, o);
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(apertureCacheDirectory(), error)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > options.size() &&
        name.compare(name.size() - options.size(), options.size(), options) == 0 &&
        isLegacyHeightChecksum(name.substr(0, name.size() - options.size()))) {
      const fs::path legacy =
          apertureCacheDirectory() / cacheName(legacyHeightfieldChecksum(field), field, o);
      return fs::exists(legacy, error) ? legacy : fs::path();
    }
  }
  return {};
}

}  // namespace

fs::path cachedAperturePath(const Heightfield& field, const BakeOptions& o) {
  return apertureCacheDirectory() / cacheName(heightfieldChecksum(field), field, o);
}

fs::path cachedHorizonsPath(const Heightfield& field, const BakeOptions& o) {
  fs::path path = cachedAperturePath(field, o);
  path.replace_extension("");
  path += "-h" + std::to_string(o.horizonDirections) + "x" + std::to_string(o.horizonBits) +
          ".horizons";
  return path;
}

HorizonMap findCachedHorizons(const Heightfield& field, const BakeOptions& options) {
  const fs::path path = cachedHorizonsPath(field, options);
  std::error_code error;
  if (!fs::exists(path, error)) return {};
  try {
    HorizonMap horizons = readHorizonMap(path);
    if (horizons.width == field.width && horizons.height == field.height &&
        horizons.directions == options.horizonDirections && horizons.bits == options.horizonBits &&
        (horizons.sourceChecksum.empty() ||  // version 2: the entry's name holds it
         horizons.sourceChecksum == heightfieldChecksum(field))) {
      return horizons;
    }
  } catch (const std::exception&) {
    // A damaged file is as good as none: the next bake replaces it.
  }
  return {};
}

fs::path findCachedAperture(const Heightfield& field, const std::string& demPath,
                            const BakeOptions& options, std::string* whyUnusable) {
  fs::path path = cachedAperturePath(field, options);
  std::error_code error;
  if (!fs::exists(path, error)) path = legacyCachedAperture(field, options);
  if (path.empty()) return {};
  try {
    ApertureMapReader reader(path.string());
    checkApertureMatchesDem(reader.header(), path.string(), field, demPath);
    // Only a map whose every pixel verifies is used: the header alone
    // survives a truncation.
    if (!reader.header().pixelChecksum) {
      throw InputError("aperture map " + path.string() +
                       " has no pixel checksum (aal:pixelChecksum): written before maps "
                       "carried one");
    }
    reader.verify();
    return path;
  } catch (const std::exception& e) {
    // Anything wrong with an entry (a bad_alloc for a damaged header's size
    // too) makes it unusable, never fatal.
    if (whyUnusable) *whyUnusable = e.what();
  }
  return {};
}

namespace {

// The input among `inputs` that `entry` is (the same file, whatever the
// names), or nothing.
std::optional<std::string> inputAt(const fs::path& entry, const std::vector<std::string>& inputs) {
  for (const std::string& input : inputs) {
    std::error_code error;
    if (!input.empty() && fs::equivalent(entry, input, error)) return input;
  }
  return std::nullopt;
}

}  // namespace

CachedAperture cachedOrBakedAperture(const Heightfield& field, const std::string& demPath,
                                     BakeOptions options, ProgressStyle progressStyle, bool quiet,
                                     const std::vector<std::string>& inputs) {
  const fs::path path = cachedAperturePath(field, options);
  std::error_code error;
  std::string whyUnusable;
  if (fs::path found = findCachedAperture(field, demPath, options, &whyUnusable); !found.empty()) {
    return {found, {}, options.horizons ? findCachedHorizons(field, options) : HorizonMap{}};
  }
  // A damaged or stale cache entry is replaced (atomically, by the
  // writer's rename), not fatal; said even when quiet, as a DEM's warnings.
  if (!whyUnusable.empty()) {
    for (char& c : whyUnusable) {
      if (c == '\n' || c == '\r') c = ' ';  // one line
    }
    std::fprintf(stderr, "warning: rebaking the cached aperture map %s: %s\n", path.c_str(),
                 whyUnusable.c_str());
  }
  ProgressReporter progress(progressStyle, "baking", "baking apertures");
  // The caller's hook (e.g. aal-view's progress bar) still hears every step.
  const std::function<void(double)> callerProgress = options.progress;
  options.progress = [&](double fraction) {
    progress.update(fraction);
    if (callerProgress) callerProgress(fraction);
  };
  BakeResult result = bakeApertures(field, options);
  progress.finish();
  result.aperture.info.source = fs::path(demPath).filename().string();
  fs::create_directories(path.parent_path(), error);
  if (error) {
    if (!quiet) {
      std::fprintf(stderr, "note: cannot create cache folder %s (%s); not caching\n",
                   path.parent_path().c_str(), error.message().c_str());
    }
    return {{}, std::move(result.aperture), std::move(result.horizons)};
  }
  // An entry that is not a regular file (a FIFO, a device, a link) is damage
  // in the cache's own folder: removed, so that the fresh entry, which is
  // written only over regular files (atomic_file.h), takes its place.
  const auto clearDamaged = [](const fs::path& entry) {
    std::error_code ignored;
    const fs::file_status status = fs::symlink_status(entry, ignored);
    if (fs::exists(status) && !fs::is_regular_file(status) && !fs::is_directory(status)) {
      fs::remove(entry, ignored);
    }
  };
  // Never over an input of this run (outputs are checked against inputs
  // before any work; the entry's name is known only from the heights).
  std::vector<std::string> protectedInputs = inputs;
  protectedInputs.push_back(demPath);
  for (const fs::path& entry :
       {path, options.horizons ? cachedHorizonsPath(field, options) : fs::path()}) {
    if (entry.empty()) continue;
    if (const std::optional<std::string> input = inputAt(entry, protectedInputs)) {
      std::fprintf(stderr,
                   "warning: not caching the aperture map: its cache entry %s is the input %s "
                   "(AAL_CACHE_DIR names another folder)\n",
                   entry.c_str(), input->c_str());
      return {{}, std::move(result.aperture), std::move(result.horizons)};
    }
  }
  clearDamaged(path);
  if (options.horizons) clearDamaged(cachedHorizonsPath(field, options));
  try {
    // The horizons first: a map found in the cache has its horizons beside it.
    if (options.horizons) writeHorizonMap(cachedHorizonsPath(field, options), result.horizons);
    writeApertureMap(path.string(), result.aperture, /*halfFloat=*/true);
    return {path, {}, std::move(result.horizons)};
  } catch (const std::exception& e) {
    if (!quiet) std::fprintf(stderr, "note: not caching the aperture map: %s\n", e.what());
  }
  return {{}, std::move(result.aperture), std::move(result.horizons)};
}

}  // namespace aal
