// An aperture map from the cache or a fresh bake on a background thread, so
// that a viewer keeps drawing (with baseline shading) while it is made.
#pragma once

#include <atomic>
#include <exception>
#include <memory>
#include <string>
#include <thread>

#include "aperture/preprocess/aperture_cache.h"
#include "aperture/preprocess/bake.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/reference/relief.h"

namespace aal {

// A finished background bake, as the viewer uploads it.
struct BakedAperture {
  std::filesystem::path path;  // where the map is cached; empty when it is not
  // The map as the device holds it (RGBA halves), read back from the cache
  // (checked against the DEM and its pixel checksum) or converted from the
  // bake in memory: on the bake's thread, not the frames'.
  HalfApertureMap map;
  HorizonMap horizons;  // as CachedAperture's
};

class BackgroundBake {
 public:
  // Starts cachedOrBakedAperture(field, demPath, options, quiet = true) on a
  // new thread, which then makes the map's halves (BakedAperture). `field` is
  // shared so it outlives the thread.
  BackgroundBake(std::shared_ptr<const Heightfield> field, std::string demPath,
                 BakeOptions options);
  // Cancels a running bake and waits for the thread: a cancelled bake stops
  // at the next azimuth and writes no cache file.
  ~BackgroundBake();
  BackgroundBake(const BackgroundBake&) = delete;
  BackgroundBake& operator=(const BackgroundBake&) = delete;

  // Fraction done in [0, 1] (1 at once for a cache hit).
  double progress() const { return progress_.load(); }
  bool finished() const { return finished_.load(); }
  // Once finished(): the map and where it is cached. Rethrows the bake's
  // error (BakeCancelled after cancel()). Call at most once.
  BakedAperture take();
  // Asks the bake to stop; finished() turns true soon after.
  void cancel() { cancel_.store(true); }

 private:
  std::shared_ptr<const Heightfield> field_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> finished_{false};
  std::atomic<double> progress_{0.0};
  BakedAperture result_;
  std::exception_ptr error_;
  std::thread thread_;
};

}  // namespace aal
