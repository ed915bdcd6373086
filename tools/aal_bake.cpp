// aal-bake: aperture maps (bent normal + visible-sky cap) from a DEM.
#include <algorithm>
#include <atomic>
#include <cctype>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <tbb/global_control.h>
#include <tbb/task_group.h>
#include <CLI/CLI.hpp>

#include "aperture/preprocess/bake.h"
#include "aperture/preprocess/local_dominance.h"
#include "aperture/preprocess/progress_reporter.h"
#include "aperture/preprocess/sky_view_factor_tiles.h"
#include "aperture/preprocess/tiled_bake.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/aperture_geotiff.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/band_labels.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/tools/bake_command_line.h"
#include "aperture/tools/options/geotiff_output_options.h"
#include "aperture/tools/options/output_options.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace {

// A per-texel result as a float32 GeoTIFF placed like the DEM, the DEM's
// voids and the result's own NaNs (openness on an open edge) NaN, its nodata
// value (sky_view_factor_tiles.h).
void writeGisRaster(const std::string& path, std::vector<float> values,
                    const aal::Heightfield& field, aal::RasterWriteOptions options,
                    const aal::RasterBandLabel& label) {
  const aal::TexelWindow whole{.width = field.width, .height = field.height};
  options.nodata = aal::markVoidsAsNodata(values, field, whole);
  options.bandLabels = {label};
  aal::writeFloatGeoTiff(path, field.width, field.height, values.data(), field.geo, options);
}

// Whether the in-memory load (heights, void mask, the fill's distances:
// ~9 bytes per texel) fits in 80 % of the memory available now
// (terrain/io/memory_budget.h; assumed to fit when unknown).
bool fitsInMemory(const aal::DemSource& dem) {
  const std::optional<uint64_t> available = aal::availableMemoryBytes();
  const double texels = static_cast<double>(dem.width()) * dem.height();
  return !available || 9.0 * texels <= 0.8 * static_cast<double>(*available);
}

struct Options : aal::SweepCommandLine {
  std::string dem;
  std::string output;
  std::string method = "sweep";
  int rays = 1024;
  std::string svfPath;
  bool svf = false;          // --svf given: with svfPath, or, tiled, into the folder
  std::string horizonsPath;  // directional horizons (docs/baking.md)
  int horizonDirections = aal::kBakeToolHorizonDirections;
  int horizonBits = aal::kBakeToolHorizonBits;
  std::string visiblePath;
  std::string positiveOpennessPath, negativeOpennessPath;  // docs/baking.md, "Openness"
  std::string localDominancePath;                          // "Local dominance"
  std::vector<int> localDominanceRadii{10, 20};
  double observerHeight = 1.7;
  std::string anisotropicSvfPath;  // "Anisotropic sky-view factor"
  double anisotropyDirection = 315;
  std::string anisotropyLevel = "low";
  std::string skyIlluminationPath;  // "Sky illumination"
  std::string skyModel = "overcast";
  int threads = 0;
  aal::ProgressOptions report;
  aal::GeoTiffOutputOptions geotiff;  // -of, -co, --overviews
  aal::RasterWriteOptions raster;     // what they ask, checked (rasterWriteOptions)
  bool lowMemory = false;
  int tileSize = 0;  // 0: tiled only above the in-memory limit
};

// The rasters a bake writes beside (or without) its map, by option; the
// paths not asked for are empty.
aal::NamedPaths rasterOutputs(const Options& o) {
  return {{"--svf", o.svfPath},
          {"--visible", o.visiblePath},
          {"--horizons", o.horizonsPath},
          {"--openness-positive", o.positiveOpennessPath},
          {"--openness-negative", o.negativeOpennessPath},
          {"--local-dominance", o.localDominancePath},
          {"--svf-anisotropic", o.anisotropicSvfPath},
          {"--sky-illumination", o.skyIlluminationPath}};
}

// Without -o a bake writes only its GIS rasters (as SAGA or RVT would):
// one must be asked for.
void checkNeedsOutput(const Options& o) {
  if (!o.output.empty()) return;
  for (const aal::RunPath& raster : rasterOutputs(o)) {
    if (!raster.path.empty()) return;
  }
  throw aal::InputError(
      "nothing to write: give -o MAP (the aperture map), or a raster alone (--svf PATH, "
      "--visible, --openness-positive, --openness-negative, --local-dominance, "
      "--svf-anisotropic, --sky-illumination or --horizons)");
}

// Without -o the sweep sums no aperture map (bakeOptions); the ray
// reference always does.
bool sumsNoMap(const Options& o) {
  return o.output.empty() && o.method == "sweep";
}

// The most texels a bake holds in memory: rasters alone (no -o) need no
// aperture sums, so they fit to twice the side.
size_t inMemoryTexelLimit(const Options& o) {
  return sumsNoMap(o) ? aal::kInMemoryRasterBakeTexelLimit : aal::kInMemoryBakeTexelLimit;
}
std::string inMemorySideLimit(const Options& o) {
  return sumsNoMap(o) ? "32768x32768" : "16384x16384";
}

void checkOutputs(const Options& o, bool tiled) {
  // Every output against the DEM's files (a VRT's sources too) and each
  // other; a tiled bake's files by their names in its folder.
  const aal::NamedPaths dem = aal::inputFiles("DEM", o.dem, /*raster=*/true);
  const aal::NamedPaths others = rasterOutputs(o);
  if (o.output.empty()) {
    // No map: the rasters alone (checkNeedsOutput made sure there is one).
    if (tiled) {
      throw aal::InputError(
          "a tiled bake writes its tiles into the folder -o: give -o FOLDER (the DEM is above " +
          inMemorySideLimit(o) + " texels, or --tile-size was given)");
    }
    aal::checkDistinctFiles(dem, others);
  } else if (tiled) {
    aal::checkTiledBakeOutput(dem, o.output, others);
  } else {
    aal::NamedPaths outputs = {{"-o", o.output}};
    aal::append(outputs, others);
    aal::checkDistinctFiles(dem, outputs);
    // Checked before the bake, not by the writer after it.
    std::string extension = std::filesystem::path(o.output).extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension != ".exr" && !aal::isGeoTiffPath(o.output)) {
      throw aal::InputError("-o " + o.output +
                            ": an aperture map is an OpenEXR file (.exr), a GeoTIFF (.tif, "
                            ".tiff), or the folder of a tiled bake (--tile-size)");
    }
    aal::requireWritableOutput(o.output);
  }
  for (const aal::RunPath& raster : others) {
    if (!raster.path.empty()) aal::requireWritableOutput(raster.path);
  }
}

// Tiled when asked, or when the DEM is above the in-memory limit; then the
// options must suit a tiled bake.
bool checkTiling(const Options& o, const aal::DemSource& dem) {
  const size_t texels = static_cast<size_t>(dem.width()) * static_cast<size_t>(dem.height());
  if (o.lowMemory && o.tileSize == 0 && texels <= inMemoryTexelLimit(o)) {
    throw aal::InputError(
        "--low-memory reads the DEM in windows for a tiled bake: give --tile-size");
  }
  const bool tooLarge = texels > inMemoryTexelLimit(o);
  if (o.tileSize == 0 && !tooLarge) return false;
  if (o.output.empty()) checkOutputs(o, true);  // says that a tiled bake needs -o FOLDER
  const std::string why = o.tileSize > 0 ? std::string("a tiled bake (--tile-size)")
                                         : "the DEM is " + std::to_string(dem.width()) + "x" +
                                               std::to_string(dem.height()) + ": above " +
                                               inMemorySideLimit(o) +
                                               " texels only a tiled bake fits in memory, which";
  if (o.method != "sweep") throw aal::InputError(why + " needs --method sweep");
  if (!o.svfPath.empty()) {
    throw aal::InputError(
        "--svf " + o.svfPath + ": " + why +
        " writes the sky-view factor into its folder (one GeoTIFF per tile and their mosaic " +
        (std::filesystem::path(o.output) / aal::kSkyViewFactorMosaicName).string() +
        "): give --svf without a path");
  }
  if (!o.visiblePath.empty() || !o.horizonsPath.empty()) {
    throw aal::InputError(why + " writes no --visible or --horizons");
  }
  if (o.raster.cog) {
    throw aal::InputError(why + " writes its sky-view factor as plain GeoTIFF tiles and a VRT " +
                          "mosaic of them: leave out -of COG (--cog); -co and --overviews apply " +
                          "to the tiles");
  }
  const std::string inOnePiece =
      ": bake them in one piece (a DEM cropped with gdal_translate -srcwin if need be)";
  if (!o.positiveOpennessPath.empty() || !o.negativeOpennessPath.empty() ||
      !o.localDominancePath.empty()) {
    throw aal::InputError(why +
                          " writes no --openness-positive, --openness-negative or "
                          "--local-dominance" +
                          inOnePiece);
  }
  if (!o.anisotropicSvfPath.empty() || !o.skyIlluminationPath.empty()) {
    throw aal::InputError(why + " writes no --svf-anisotropic or --sky-illumination" + inOnePiece);
  }
  aal::checkSweepOptions(o);
  return true;
}

// The checks that need the DEM's size: --near-reach and --svf without a
// path are for tiled bakes, and the reach must cover the DEM's cells.
void checkTiledOptions(const Options& o, const aal::DemSource& dem, const aal::DemLoadOptions& load,
                       bool tiled) {
  if (!tiled && o.nearReach > 0) {
    throw aal::InputError("--near-reach is for tiled bakes without --max-distance (--tile-size)");
  }
  if (tiled && o.nearReach > 0) {
    aal::DemLoadOptions quiet = load;
    quiet.warn = nullptr;  // said once, below
    aal::TiledBakeOptions reach;
    reach.farField.nearReachM = o.nearReach;
    aal::checkNearReach(aal::demGeometry(dem, quiet), reach);
  }
  if (!tiled && o.svf && o.svfPath.empty()) {
    throw aal::InputError(
        "--svf needs a path (a GeoTIFF) for a bake into one file; only a tiled bake "
        "(--tile-size) writes it into its folder");
  }
}

// Refused with the numbers before anything is allocated, not by the
// allocator half-way through (memory_budget.h).
void requireInMemoryBake(const Options& o, const aal::DemSource& dem) {
  const double texels = double(dem.width()) * double(dem.height());
  // Negative openness: its sums and the inverted heights it sweeps.
  const double perTexel =
      aal::kInMemoryBakeBytesPerTexel - (sumsNoMap(o) ? aal::kApertureSumBytesPerTexel : 0) +
      (o.svf ? 4 : 0) + (o.visiblePath.empty() ? 0 : 4) + (o.positiveOpennessPath.empty() ? 0 : 4) +
      (o.negativeOpennessPath.empty() ? 0 : 8) + (o.localDominancePath.empty() ? 0 : 4) +
      (o.anisotropicSvfPath.empty() ? 0 : 4) + (o.skyIlluminationPath.empty() ? 0 : 4) +
      (o.horizonsPath.empty() ? 0 : o.horizonDirections);
  aal::requireMemory(
      o.dem, texels * perTexel,
      "its bake in memory (" + std::to_string(std::lround(perTexel)) + " bytes per texel)",
      std::string("bake it in tiles (") + (o.output.empty() ? "-o FOLDER " : "") +
          "--tile-size 4096; with --low-memory the DEM is read a window at a time)");
}

// The DEM as the bake reads it: its geometry always, its heights unless
// the tiles read it in windows (`inBands`).
struct BakeDem {
  aal::Heightfield geometry;
  aal::Heightfield field;  // empty when read in windows
  double readSeconds = 0;
};

BakeDem readBakeDem(const Options& o, const aal::DemSource& dem, const aal::DemLoadOptions& load,
                    bool inBands, std::chrono::steady_clock::time_point readStart) {
  // The samples first: DemSource finds the CRS while they decode.
  std::optional<aal::RawDem> samples;
  if (!inBands) samples = dem.readAll();
  BakeDem read;
  read.geometry = aal::demGeometry(dem, load);
  if (samples) {
    aal::DemLoadOptions quiet = load;
    quiet.warn = nullptr;  // demGeometry has said it
    read.field = aal::heightfieldFromRaw(std::move(*samples), o.dem, quiet);
  }
  read.readSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - readStart).count();
  return read;
}

// The bake's options, less its progress and cancel; InputError when the
// method cannot give what is asked.
aal::BakeOptions bakeOptions(const Options& o) {
  aal::BakeOptions bake;
  bake.method = o.method == "rays" ? aal::BakeMethod::Rays : aal::BakeMethod::Sweep;
  aal::applySweepOptions(o, bake);
  bake.rays = o.rays;
  bake.skyViewFactor = o.svf;
  // Without -o only GIS rasters are written: no aperture map is summed.
  bake.apertureMap = !sumsNoMap(o);
  bake.visibleFraction = !o.visiblePath.empty();
  if (bake.skyViewFactor && bake.method == aal::BakeMethod::Rays) {
    throw aal::InputError("--svf needs --method sweep (the ray reference has no horizons)");
  }
  bake.positiveOpenness = !o.positiveOpennessPath.empty();
  bake.negativeOpenness = !o.negativeOpennessPath.empty();
  if ((bake.positiveOpenness || bake.negativeOpenness) && bake.method == aal::BakeMethod::Rays) {
    throw aal::InputError(
        "--openness-positive and --openness-negative need --method sweep (the ray reference has "
        "no horizons)");
  }
  if (bake.negativeOpenness && bake.curvature) {
    throw aal::InputError(
        "--openness-negative does not take --curvature (the inverted DEM's sweep would raise "
        "distant terrain, not drop it)");
  }
  bake.anisotropicSkyViewFactor = !o.anisotropicSvfPath.empty();
  bake.anisotropy = aal::anisotropyLevel(o.anisotropyLevel == "high", o.anisotropyDirection);
  bake.skyIllumination = !o.skyIlluminationPath.empty();
  bake.skyModel = o.skyModel == "uniform" ? aal::SkyModel::Uniform : aal::SkyModel::Overcast;
  if ((bake.anisotropicSkyViewFactor || bake.skyIllumination) &&
      bake.method == aal::BakeMethod::Rays) {
    throw aal::InputError(
        "--svf-anisotropic and --sky-illumination need --method sweep (the ray reference has no "
        "horizons)");
  }
  if (o.localDominanceRadii[0] > o.localDominanceRadii[1]) {
    throw aal::InputError("--local-dominance-radii " + std::to_string(o.localDominanceRadii[0]) +
                          " " + std::to_string(o.localDominanceRadii[1]) +
                          ": the inner radius must not exceed the outer");
  }
  bake.horizons = !o.horizonsPath.empty();
  if (bake.horizons && bake.method == aal::BakeMethod::Rays) {
    throw aal::InputError("--horizons needs --method sweep (the ray reference has no horizons)");
  }
  bake.horizonDirections = o.horizonDirections;
  bake.horizonBits = o.horizonBits;
  if (bake.horizons && o.azimuths % o.horizonDirections != 0) {
    throw aal::InputError("--horizons needs --azimuths a multiple of --horizon-directions " +
                          std::to_string(o.horizonDirections) +
                          " (the horizons are the sweep's own)");
  }
  return bake;
}

aal::TiledBakeOptions tiledBakeOptions(const Options& o, const std::string& source,
                                       const aal::TiledBakeLock* lock) {
  aal::TiledBakeOptions tiling;
  tiling.tileSize = o.tileSize > 0 ? o.tileSize : aal::kDefaultTileSize;
  tiling.halfFloat = !o.fullFloat;
  tiling.compression = aal::mapCompression(o);
  tiling.sourceName = source;
  tiling.lock = lock;
  tiling.farField.nearReachM = o.nearReach;
  tiling.skyViewFactorRaster = o.raster;
  return tiling;
}

// How the bake runs: in one piece, in tiles, or in tiles read in windows.
struct BakePlan {
  bool tiled = false, inBands = false;
  aal::BakeOptions bake;
  aal::TiledBakeOptions tiling;
};

// What the bake made: the maps of a bake in one piece, or the tiles'
// counts (the tiles are in the folder already).
struct Baked {
  aal::BakeResult result;
  std::vector<float> localDominance;  // --local-dominance
  aal::TiledBakeSummary tiles;
  double seconds = 0;
};

aal::LocalDominanceOptions localDominanceOptions(const Options& o) {
  aal::LocalDominanceOptions options;
  options.minRadiusCells = o.localDominanceRadii[0];
  options.maxRadiusCells = o.localDominanceRadii[1];
  options.observerHeightM = o.observerHeight;
  options.cancel = &aal::interruptFlag();
  return options;
}

// The bake; nullopt when interrupted (said on stderr).
std::optional<Baked> bakeOrInterrupted(const Options& o, const aal::DemSource& dem,
                                       const BakeDem& read, const BakePlan& plan,
                                       aal::ProgressReporter& progress) {
  const auto start = std::chrono::steady_clock::now();
  Baked baked;
  try {
    if (plan.inBands) {
      baked.tiles = aal::bakeTiledInBands(dem, read.geometry, plan.bake, plan.tiling, o.output);
    } else if (plan.tiled) {
      baked.tiles = aal::bakeTiled(read.field, plan.bake, plan.tiling, o.output);
    } else {
      baked.result = aal::bakeApertures(read.field, plan.bake);
      if (!o.localDominancePath.empty()) {
        baked.localDominance = aal::localDominance(read.field, localDominanceOptions(o));
      }
    }
  } catch (const aal::BakeCancelled&) {
    progress.finish();
    if (plan.tiled) {
      std::fprintf(stderr,
                   "aal-bake: interrupted; the finished tiles are kept in %s: run the same "
                   "command again to resume\n",
                   o.output.c_str());
    } else {
      std::fprintf(stderr, "aal-bake: interrupted; nothing was written\n");
    }
    return std::nullopt;
  }
  progress.finish();
  baked.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return baked;
}

// The map of a bake in one piece and the extra rasters, each file on its
// own thread (they are independent, and a file's compression runs on one
// core); false when interrupted (said on stderr). The writers poll the
// interrupt too: each output is whole or absent.
bool writeOutputs(const Options& o, bool tiled, Baked& baked, const aal::Heightfield& field,
                  const std::string& source) {
  aal::BakeResult& result = baked.result;
  tbb::task_group writers;
  const auto raster = [&](const std::string& path, std::vector<float>& values,
                          const aal::RasterBandLabel& label) {
    if (!path.empty()) {
      writers.run([&, label] { writeGisRaster(path, std::move(values), field, o.raster, label); });
    }
  };
  try {
    if (!tiled && !o.output.empty()) {
      result.aperture.info.source = source;
      writers.run([&] {
        if (aal::isGeoTiffPath(o.output)) {
          aal::writeApertureGeoTiff(o.output, result.aperture, field.geo, o.raster);
        } else {
          aal::writeApertureMap(o.output, result.aperture, !o.fullFloat, aal::mapCompression(o));
        }
      });
    }
    raster(o.svfPath, result.skyViewFactor, aal::skyViewFactorBandLabel());
    raster(o.visiblePath, result.visibleFraction, aal::visibleFractionBandLabel());
    if (!o.horizonsPath.empty()) {
      writers.run([&] { aal::writeHorizonMap(o.horizonsPath, result.horizons); });
    }
    raster(o.positiveOpennessPath, result.positiveOpenness, aal::positiveOpennessBandLabel());
    raster(o.negativeOpennessPath, result.negativeOpenness, aal::negativeOpennessBandLabel());
    raster(o.anisotropicSvfPath, result.anisotropicSkyViewFactor,
           aal::anisotropicSkyViewFactorBandLabel());
    raster(o.skyIlluminationPath, result.skyIllumination,
           aal::skyIlluminationBandLabel(o.skyModel == "overcast"));
    raster(o.localDominancePath, baked.localDominance, aal::localDominanceBandLabel());
    writers.wait();
  } catch (const aal::Interrupted&) {
    writers.wait();
    std::fprintf(stderr,
                 "aal-bake: interrupted while writing; the outputs written before are kept, those "
                 "being written were removed\n");
    return false;
  } catch (...) {
    writers.wait();  // the others finish before their buffers go
    throw;
  }
  return true;
}

// A tiled bake's part of the summary: its tiles, baked and resumed, and the
// windows' reads.
std::string tiledLayout(const BakePlan& plan, const aal::TiledBakeSummary& tiles,
                        const aal::Heightfield& geometry) {
  std::string layout = ", " + std::to_string(plan.tiling.tileSize) + "-texel tiles" +
                       (plan.inBands ? " read in windows" : "") + " (" +
                       std::to_string(tiles.baked) + " baked, " + std::to_string(tiles.resumed) +
                       " resumed)";
  if (plan.inBands && tiles.baked > 0) {
    char reads[96];
    std::snprintf(reads, sizeof reads, ", windows of %.3g DEM texels read per texel",
                  static_cast<double>(tiles.texelsRead) / geometry.texelCount());
    layout += reads;
  }
  return layout;
}

// The one line on stderr: the DEM, the layout, the method, the rate and
// the times.
void printSummary(const Options& o, const BakePlan& plan, const Baked& baked, const BakeDem& read,
                  double writeSeconds, const std::string& source) {
  // A resumed tiled bake counts only the texels it baked.
  double texels = static_cast<double>(read.geometry.texelCount());
  std::string layout;
  if (plan.tiled) {
    layout = tiledLayout(plan, baked.tiles, read.geometry);
    if (baked.tiles.tiles > 0) texels *= static_cast<double>(baked.tiles.baked) / baked.tiles.tiles;
  }
  const bool sweep = plan.bake.method == aal::BakeMethod::Sweep;
  const double work = texels * (sweep ? o.azimuths : o.rays);
  std::string target = o.output;
  if (target.empty()) {  // the rasters alone
    for (const aal::RunPath& raster : rasterOutputs(o)) {
      if (!raster.path.empty()) target += (target.empty() ? "" : ", ") + raster.path;
    }
  }
  if (plan.tiled && o.svf) {
    target += " (sky-view factor: " +
              (std::filesystem::path(o.output) / aal::kSkyViewFactorMosaicName).string() + ")";
  }
  // A bake that only resumed finished tiles has no rate to report.
  char rate[64] = "nothing baked";
  if (work > 0) {
    std::snprintf(rate, sizeof rate, "%.3g texel-%s/s", work / baked.seconds,
                  sweep ? "azimuths" : "rays");
  }
  std::fprintf(
      stderr,
      "aal-bake: %s %dx%d%s, %s, %s in %.2f s (%s); DEM read in %.2f s, output "
      "written in %.2f s -> %s\n",
      source.c_str(), read.geometry.width, read.geometry.height, layout.c_str(), o.method.c_str(),
      (sweep ? std::to_string(o.azimuths) + " azimuths" : std::to_string(o.rays) + " rays").c_str(),
      baked.seconds, rate, read.readSeconds, writeSeconds, target.c_str());
}

int run(Options& o) {
  o.raster = aal::rasterWriteOptions(o.geotiff);
  checkNeedsOutput(o);
  // Outputs are checked before minutes of work, not after (again once the
  // DEM's size has decided the tiling).
  const bool askedTiled = o.tileSize > 0 || std::filesystem::is_directory(o.output);
  checkOutputs(o, askedTiled);
  // A folder another bake is writing is refused before the DEM is read
  // (exit 1, TiledBakeBusy); the lock is held to the end of the bake.
  std::optional<aal::TiledBakeLock> lock;
  if (askedTiled && std::filesystem::is_directory(o.output)) lock.emplace(o.output);
  const aal::DemLoadOptions load = aal::demLoadOptions(o, askedTiled || o.lowMemory);
  const auto readStart = std::chrono::steady_clock::now();
  const aal::DemSource dem(o.dem, load);
  BakePlan plan;
  plan.tiled = checkTiling(o, dem);
  checkTiledOptions(o, dem, load, plan.tiled);
  if (plan.tiled != askedTiled) checkOutputs(o, plan.tiled);
  if (!plan.tiled) requireInMemoryBake(o, dem);
  // A tiled bake of a DEM that does not fit in memory reads it in windows.
  plan.inBands = plan.tiled && (o.lowMemory || !fitsInMemory(dem));
  const BakeDem read = readBakeDem(o, dem, load, plan.inBands, readStart);

  plan.bake = bakeOptions(o);
  aal::ProgressReporter progress(o.report.style(), "baking", "aal-bake");
  plan.bake.progress = [&](double fraction) { progress.update(fraction); };
  // First Ctrl-C or SIGTERM: stop cleanly, nothing written; a second kills.
  plan.bake.cancel = &aal::interruptFlag();
  const int threads =
      o.threads > 0 ? o.threads : static_cast<int>(std::thread::hardware_concurrency());
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<size_t>(std::max(1, threads)));
  const std::string source = std::filesystem::path(o.dem).filename().string();
  plan.tiling = tiledBakeOptions(o, source, lock ? &*lock : nullptr);
  std::optional<Baked> baked = bakeOrInterrupted(o, dem, read, plan, progress);
  if (!baked) return aal::kExitFailure;

  const auto writeStart = std::chrono::steady_clock::now();
  if (!writeOutputs(o, plan.tiled, *baked, read.field, source)) return aal::kExitFailure;
  const double writeSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - writeStart).count();
  if (!o.report.quiet) printSummary(o, plan, *baked, read, writeSeconds, source);
  return aal::kExitOk;
}

// --svf-anisotropic and --sky-illumination with their settings.
void addSkyOptions(CLI::App& app, Options& o) {
  CLI::Option* anisotropic = app.add_option(
      "--svf-anisotropic", o.anisotropicSvfPath,
      "also write the anisotropic sky-view factor (Zaksek et al.; RVT's weights): as --svf, each "
      "azimuth's term weighted by (1 - m) cos((A - D) / 2)^p + m, A its azimuth, D "
      "--svf-anisotropy-direction; p, m by --svf-anisotropy-level; a float32 GeoTIFF placed like "
      "the DEM, voids nodata (docs/baking.md)");
  app.add_option("--svf-anisotropy-direction", o.anisotropyDirection,
                 "main direction of --svf-anisotropic, in degrees clockwise from north (as RVT; "
                 "the sky there weighs most)")
      ->check(CLI::Range(0.0, 360.0))
      ->needs(anisotropic)
      ->capture_default_str();
  app.add_option("--svf-anisotropy-level", o.anisotropyLevel,
                 "low: p = 4, m = 0.4; high: p = 8, m = 0.1 (RVT's levels)")
      ->check(CLI::IsMember({"low", "high"}))
      ->needs(anisotropic)
      ->capture_default_str();
  CLI::Option* sky = app.add_option(
      "--sky-illumination", o.skyIlluminationPath,
      "also write the diffuse illumination under the sky, shadowed by the horizons: the "
      "irradiance from the sky above the horizontal, the horizon and the tangent plane, over "
      "that of a horizontal plane under the open sky (1 there), as a float32 GeoTIFF placed "
      "like the DEM, voids nodata (docs/baking.md)");
  app.add_option("--sky-model", o.skyModel,
                 "sky radiance of --sky-illumination: uniform, or overcast (the CIE standard "
                 "overcast sky, (1 + 2 sin elevation) / 3)")
      ->check(CLI::IsMember({"uniform", "overcast"}))
      ->needs(sky)
      ->capture_default_str();
}

// --svf, --horizons with its directions and bits, --visible: what the bake
// writes besides the map. Returns --svf, which may come without a path.
CLI::Option* addExtraOutputOptions(CLI::App& app, Options& o) {
  CLI::Option* svf = app.add_option(
      "--svf", o.svfPath,
      "also write the sky-view factor (Zaksek) as a float32 GeoTIFF placed like the DEM (its "
      "voids NaN, the nodata value); a tiled bake takes --svf without a path and writes it into "
      "its folder: "
      "svf_ROW_COL.tif per tile and their mosaic sky_view_factor.vrt");
  svf->expected(0, 1);
  app.add_option(
      "--horizons", o.horizonsPath,
      "also write the directional horizons (--horizon-directions azimuths, --horizon-bits "
      "each) for aal-render --mode horizon (docs/baking.md)");
  app.add_option("--horizon-directions", o.horizonDirections,
                 "azimuths of --horizons: 4, 8, 12 or 16")
      ->check(CLI::IsMember({4, 8, 12, 16}))
      ->capture_default_str();
  app.add_option("--horizon-bits", o.horizonBits,
                 "bits of each horizon code: 8 (elevations to 90 degrees) or 4 (to 45 degrees, "
                 "coarser: more error, and no smaller, as a code takes a byte either way; "
                 "docs/comparison.md)")
      ->check(CLI::IsMember({4, 8}))
      ->capture_default_str();
  app.add_option(
      "--visible", o.visiblePath,
      "also write the visible fraction Omega/2pi as a float32 GeoTIFF placed like the DEM (its "
      "voids NaN, the nodata value)");
  app.add_option("--openness-positive", o.positiveOpennessPath,
                 "also write positive topographic openness (Yokoyama): the mean over the "
                 "--azimuths of 90 degrees minus the highest signed elevation angle within "
                 "--max-distance (else the whole DEM), in degrees, as a float32 GeoTIFF placed "
                 "like the DEM; 90 on a plane, above on ridges; nodata at voids and, with --edge "
                 "open, on the DEM's outer ring (docs/baking.md)");
  app.add_option("--openness-negative", o.negativeOpennessPath,
                 "also write negative openness: 90 degrees plus the mean lowest elevation angle, "
                 "as --openness-positive; 90 on a plane, above in valleys; a second sweep over "
                 "the inverted DEM, about as long again; not with --curvature");
  CLI::Option* dominance =
      app.add_option("--local-dominance", o.localDominancePath,
                     "also write local dominance (Hesse; RVT's definition): how far an observer "
                     "--observer-height above each texel looks down on the ring of "
                     "--local-dominance-radii cells around it, relative to a plane (1 on a plane, "
                     "above on peaks, 0 in hollows deeper than the observer), as a float32 GeoTIFF "
                     "placed like the DEM; voids nodata (docs/baking.md)");
  app.add_option("--local-dominance-radii", o.localDominanceRadii,
                 "inner and outer radius of --local-dominance's ring, in cells")
      ->expected(2)
      ->check(CLI::Range(1, 1000))
      ->needs(dominance)
      ->capture_default_str();
  app.add_option("--observer-height", o.observerHeight,
                 "metres of the observer above each texel for --local-dominance")
      ->check(CLI::PositiveNumber)
      ->needs(dominance)
      ->capture_default_str();
  addSkyOptions(app, o);
  return svf;
}

// --tile-size, --near-reach, --low-memory.
void addTiledBakeOptions(CLI::App& app, Options& o) {
  app.add_option("--tile-size", o.tileSize,
                 "bake in tiles of N x N texels into the folder -o, resumable (without "
                 "--max-distance the far horizons come from a pyramid); DEMs above 16384x16384 "
                 "texels (32768x32768 for GIS rasters without -o) are always baked tiled, in "
                 "tiles of 4096")
      ->check(CLI::Range(aal::kMinTileSize, aal::kMaxTileSize));
  aal::addNearReachOption(app, o);
  app.add_flag("--low-memory", o.lowMemory,
               "read the DEM one window at a time (a tile plus its halo, slid along the tile "
               "row): a tiled bake then needs memory for two windows, not the DEM; automatic "
               "when the DEM "
               "does not fit in memory; the DEM must have no voids (gdal_fillnodata.py fills "
               "them)");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app(
      "Bakes the aperture map of a DEM: for every texel the visible sky as a spherical cap, "
      "its\nbent normal (mean unoccluded direction) and arc length r = acos(1 - Omega/2pi), "
      "written as\nEXR (RGB = bent normal, A = r), or as a float32 GeoTIFF of four bands placed "
      "like the\nDEM for GIS tools (-o map.tif). Horizons come from the whole DEM (no "
      "distance limit\nunless --max-distance).\n\nAbove 16384x16384 texels (the in-memory bake's "
      "~20 bytes per texel, ~22 GB at the\nnext size up, would not fit 24 GiB) the DEM is baked in "
      "tiles into the folder -o (rasters alone, without -o: above 32768x32768). Each tile\nis "
      "baked from itself plus a halo: with "
      "--max-distance the terrain within that distance,\nequal to the in-memory bake; without, "
      "128 cells, and the horizons beyond from a pyramid\nof the whole DEM's block maxima (a far "
      "field, close to the in-memory bake). An "
      "interrupted tiled bake resumes from its\nfinished tiles when run again. aal-render and "
      "aal-view read the folder as the map. A folder\nholds one bake: while another aal-bake "
      "runs in it a bake is refused (exit 1), and so is\na bake of another DEM or with other "
      "options (exit 2).\n\n" +
          aal::demFormatsHelp(),
      "aal-bake");
  Options o;
  app.add_option("dem", o.dem, "input DEM")->required();
  app.add_option("-o,--output", o.output,
                 "output aperture map: .exr (OpenEXR, RGB = bent normal, A = arc length), or "
                 ".tif/.tiff (a float32 GeoTIFF placed like the DEM, bands bent normal x, y, z "
                 "and arc length; -of, -co and --overviews apply), or the output folder of a "
                 "tiled bake; without it the bake writes only the rasters asked for (--svf PATH, "
                 "--openness-positive, ...), at least one");
  app.add_option("--method", o.method,
                 "sweep: exact horizons by line sweep (fast); rays: brute-force reference")
      ->check(CLI::IsMember({"sweep", "rays"}))
      ->capture_default_str();
  app.add_option("--rays", o.rays, "rays per texel for --method rays")
      ->check(CLI::Range(16, 1 << 20))
      ->capture_default_str();
  aal::addSweepOptions(app, o);
  CLI::Option* svf = addExtraOutputOptions(app, o);
  app.add_option("--threads", o.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 1024));
  addTiledBakeOptions(app, o);
  // A tiled bake's SVF tiles take -co and --overviews (checkTiling refuses
  // -of COG for them).
  aal::addGeoTiffOutputOptions(app, o.geotiff,
                               "the GeoTIFFs (--svf, --visible, the openness, local dominance, "
                               "anisotropic SVF and sky illumination rasters, a .tif map)");
  aal::addMapStorageOptions(app, o);
  aal::addProgressOptions(app, o.report);

  aal::GdalArguments arguments(argc, argv);
  return aal::runTool(app, arguments.argc(), arguments.argv(), [&] {
    o.svf = svf->count() > 0;
    return run(o);
  });
}
