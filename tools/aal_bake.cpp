// aal-bake: aperture maps (bent normal + visible-sky cap) from a DEM.
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "aperture_map.h"
#include "atomic_file.h"
#include "bake.h"
#include "dem_format.h"
#include "dem_loader.h"
#include "geotiff_writer.h"
#include "progress.h"
#include "tool_main.h"
#include "tool_options.h"

namespace {

std::atomic<bool> gInterrupted{false};

// First Ctrl-C: stop the bake cleanly (no output); a second one kills.
extern "C" void onInterrupt(int signal) {
  gInterrupted.store(true);
  std::signal(signal, SIG_DFL);
}

struct Options {
  std::string dem;
  std::string output;
  std::string method = "sweep";
  int azimuths = 64;
  int rays = 1024;
  std::optional<double> cellSize;
  std::optional<double> zScale;
  std::string edge = "open";
  bool curvature = false;
  double refraction = 0.13;
  double maxDistance = 0;
  std::string svfPath;
  std::string visiblePath;
  int threads = 0;
  bool quiet = false;
  bool fullFloat = false;
};

void checkOutputs(const Options& o) {
  for (const std::string& path : {o.output, o.svfPath, o.visiblePath}) {
    if (path.empty()) continue;
    aal::requireWritableOutput(path);
  }
}

std::vector<float> visibleFractions(const aal::ApertureMap& map) {
  std::vector<float> visible(map.texelCount());
  for (size_t i = 0; i < visible.size(); ++i) visible[i] = map.visibleFraction(i);
  return visible;
}

int run(const Options& o) {
  checkOutputs(o);  // before minutes of work, not after
  aal::DemLoadOptions load;
  load.cellSizeM = o.cellSize;
  load.zScale = o.zScale;
  aal::Heightfield field = aal::loadDem(o.dem, load);

  aal::BakeOptions bake;
  bake.method = o.method == "rays" ? aal::BakeMethod::Rays : aal::BakeMethod::Sweep;
  bake.azimuths = o.azimuths;
  bake.rays = o.rays;
  bake.clampEdge = o.edge == "clamp";
  bake.curvature = o.curvature;
  bake.refraction = o.refraction;
  bake.maxDistanceM = o.maxDistance;
  bake.skyViewFactor = !o.svfPath.empty();
  if (bake.skyViewFactor && bake.method == aal::BakeMethod::Rays) {
    throw aal::InputError("--svf needs --method sweep (the ray reference has no horizons)");
  }
  aal::ProgressBar progress("aal-bake", !o.quiet);
  bake.progress = [&](double fraction) { progress.update(fraction); };
  bake.cancel = &gInterrupted;

  const int threads =
      o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency());
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<size_t>(std::max(1, threads)));
  const auto start = std::chrono::steady_clock::now();
  aal::BakeResult result;
  try {
    result = aal::bakeApertures(field, bake);
  } catch (const aal::BakeCancelled&) {
    progress.finish();
    std::fprintf(stderr, "aal-bake: interrupted; nothing was written\n");
    return aal::kExitFailure;
  }
  progress.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  result.aperture.info.source = std::filesystem::path(o.dem).filename().string();
  aal::writeApertureMap(o.output, result.aperture, !o.fullFloat);
  if (!o.svfPath.empty()) {
    aal::writeFloatGeoTiff(o.svfPath, field.width, field.height, result.skyViewFactor.data(),
                           field.geo);
  }
  if (!o.visiblePath.empty()) {
    const std::vector<float> visible = visibleFractions(result.aperture);
    aal::writeFloatGeoTiff(o.visiblePath, field.width, field.height, visible.data(), field.geo);
  }

  const double work = static_cast<double>(field.texelCount()) *
                      (bake.method == aal::BakeMethod::Sweep ? o.azimuths : o.rays);
  if (!o.quiet) {
    std::fprintf(stderr, "aal-bake: %s %dx%d, %s, %s in %.2f s (%.3g texel-%s/s) -> %s\n",
                 result.aperture.info.source.c_str(), field.width, field.height, o.method.c_str(),
                 (bake.method == aal::BakeMethod::Sweep ? std::to_string(o.azimuths) + " azimuths"
                                                        : std::to_string(o.rays) + " rays")
                     .c_str(),
                 seconds, work / seconds,
                 bake.method == aal::BakeMethod::Sweep ? "azimuths" : "rays", o.output.c_str());
  }
  return aal::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Bakes the aperture map of a DEM: for every texel the visible sky as a spherical cap, "
      "its\nbent normal (mean unoccluded direction) and arc length r = acos(1 - Omega/2pi), "
      "written as\nEXR (RGB = bent normal, A = r). Horizons come from the whole DEM (no "
      "distance limit\nunless --max-distance).\n\n" +
          aal::demFormatsHelp(),
      "aal-bake");
  Options o;
  app.add_option("dem", o.dem, "input DEM")->required();
  app.add_option("-o,--output", o.output, "output aperture map (.exr)")->required();
  app.add_option("--method", o.method,
                 "sweep: exact horizons by line sweep (fast); rays: brute-force reference")
      ->check(CLI::IsMember({"sweep", "rays"}))
      ->capture_default_str();
  app.add_option("--azimuths", o.azimuths, "azimuth slices of the sweep")
      ->check(CLI::Range(4, 4096))
      ->capture_default_str();
  app.add_option("--rays", o.rays, "rays per texel for --method rays")
      ->check(CLI::Range(16, 1 << 20))
      ->capture_default_str();
  app.add_option("--cell-size", o.cellSize, "texel spacing in metres (overrides the file)")
      ->check(CLI::PositiveNumber);
  app.add_option("--z-scale", o.zScale, "metres per height unit (overrides the file)")
      ->check(CLI::PositiveNumber);
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
                 "only terrain within this many metres counts (0 = all; slower when set)")
      ->check(CLI::NonNegativeNumber);
  app.add_option("--svf", o.svfPath, "also write the sky-view factor (Zaksek) as float32 GeoTIFF");
  app.add_option("--visible", o.visiblePath,
                 "also write the visible fraction Omega/2pi as float32 GeoTIFF");
  app.add_option("--threads", o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  app.add_flag("--float", o.fullFloat, "store 32-bit floats instead of 16-bit halves");
  app.add_flag("-q,--quiet", o.quiet, "no progress and no summary");

  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  return aal::runTool(app, argc, argv, [&] { return run(o); });
}
