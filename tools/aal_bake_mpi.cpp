// aal-bake-mpi: aal-bake's tiled bake across the ranks of an MPI job
// (mpirun -np N aal-bake-mpi DEM --tile-size T -o FOLDER; docs/baking.md,
// "Across machines: MPI"). The same folder, bit for bit, as aal-bake's.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <optional>
#include <string>
#include <thread>

#include <tbb/global_control.h>
#include <CLI/CLI.hpp>

#include "aperture/preprocess/mpi_tiled_bake.h"
#include "aperture/preprocess/progress_reporter.h"
#include "aperture/preprocess/sky_view_factor_tiles.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/tools/bake_command_line.h"
#include "aperture/tools/options/geotiff_output_options.h"
#include "aperture/tools/options/output_options.h"
#include "aperture/tools/tool_main.h"
#include "aperture/tools/tool_options.h"
#include "aperture/tools/tool_paths.h"

namespace {

struct Options : aal::SweepCommandLine {
  std::string dem;
  std::string output;
  int tileSize = aal::kDefaultTileSize;
  bool svf = false;
  aal::GeoTiffOutputOptions geotiff;  // -co, --overviews of the SVF tiles
  int threads = 0;
  aal::ProgressOptions report;  // -q, --progress (rank 0's)
};

// Ranks of this job on this host: a node's cores are shared among them.
int ranksOnThisHost() {
  MPI_Comm host;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &host);
  int ranks = 1;
  MPI_Comm_size(host, &ranks);
  MPI_Comm_free(&host);
  return ranks;
}

// AAL_BAKE_MPI_KILL_AT=ROW,COLUMN (for the tests): the rank given tile
// (ROW, COLUMN) to bake kills itself with SIGKILL before baking it, as a
// node failure would. Every tile is given to some rank: the kill always
// happens, whichever rank is fastest.
aal::MpiTiledBakeHooks testHooks() {
  aal::MpiTiledBakeHooks hooks;
  const char* kill = std::getenv("AAL_BAKE_MPI_KILL_AT");
  int killRow = -1, killColumn = -1;
  if (kill && std::sscanf(kill, "%d,%d", &killRow, &killColumn) == 2) {
    hooks.beforeTile = [killRow, killColumn](int row, int column) {
      if (row == killRow && column == killColumn) std::raise(SIGKILL);
    };
  }
  return hooks;
}

// Rank 0 checks what can be checked before the DEM is read (the output
// folder, the DEM's file) and tells the others whether to go on: one
// message, not one per rank.
int checkOnRankZero(int rank, const Options& o) {
  int status = 0;
  if (rank == 0) {
    try {
      aal::checkTiledBakeOutput(aal::inputFiles("DEM", o.dem, /*raster=*/true), o.output);
      aal::checkSweepOptions(o);
      aal::rasterWriteOptions(o.geotiff);
      const aal::DemLoadOptions load = aal::demLoadOptions(o, /*windowed=*/true);
      const aal::DemSource dem(o.dem, load);
      const aal::Heightfield geometry = aal::demGeometry(dem, load);  // its warnings, once
      aal::TiledBakeOptions reach;
      reach.farField.nearReachM = o.nearReach;
      aal::checkNearReach(geometry, reach);
    } catch (const aal::InputError& e) {
      std::fprintf(stderr, "aal-bake-mpi: %s\n", e.what());
      status = aal::kExitBadInput;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "aal-bake-mpi: error: %s\n", e.what());
      status = aal::kExitFailure;
    }
  }
  MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
  return status;
}

int run(const Options& o) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (const int status = checkOnRankZero(rank, o); status != 0) return status;

  // Every rank opens the DEM (a rank on another host may not reach it).
  aal::DemLoadOptions load = aal::demLoadOptions(o, /*windowed=*/true);
  load.warn = nullptr;  // rank 0 has given them
  std::optional<aal::DemSource> dem;
  aal::Heightfield geometry;
  int status = 0;
  try {
    dem.emplace(o.dem, load);
    geometry = aal::demGeometry(*dem, load);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "aal-bake-mpi: rank %d: %s\n", rank, e.what());
    status = dynamic_cast<const aal::InputError*>(&e) ? aal::kExitBadInput : aal::kExitFailure;
  }
  MPI_Allreduce(MPI_IN_PLACE, &status, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (status != 0) return status;

  aal::BakeOptions bake;
  aal::applySweepOptions(o, bake);
  bake.skyViewFactor = o.svf;
  bake.cancel = &aal::interruptFlag();
  aal::TiledBakeOptions tiling;
  tiling.tileSize = o.tileSize;
  tiling.halfFloat = !o.fullFloat;
  tiling.compression = aal::mapCompression(o);
  tiling.sourceName = std::filesystem::path(o.dem).filename().string();
  tiling.farField.nearReachM = o.nearReach;
  tiling.skyViewFactorRaster = aal::rasterWriteOptions(o.geotiff);  // checked on rank 0

  // By default a host's cores are shared among its ranks.
  const int cores = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  const int threads = o.threads > 0 ? o.threads : std::max(1, cores / ranksOnThisHost());
  tbb::global_control parallelism(tbb::global_control::max_allowed_parallelism,
                                  static_cast<size_t>(threads));

  // Rank 0 reports the share of tiles finished, whoever baked them.
  std::optional<aal::ProgressReporter> progress;
  if (rank == 0) {
    progress.emplace(o.report.style(), "baking", "baking tiles");
    bake.progress = [&progress](double fraction) { progress->update(fraction); };
  }
  const auto start = std::chrono::steady_clock::now();
  aal::MpiTiledBakeSummary summary;
  try {
    summary =
        aal::bakeTiledMpi(MPI_COMM_WORLD, *dem, geometry, bake, tiling, o.output, testHooks());
  } catch (const aal::MpiPeerFailed& e) {
    return e.exitCode();  // rank 0 has said why
  } catch (const aal::MpiTileFailed& e) {
    // The other ranks would wait for this one's tiles: end the job.
    std::fprintf(stderr, "aal-bake-mpi: rank %d: %s\n", rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, e.exitCode());
    return e.exitCode();
  } catch (const aal::BakeCancelled&) {
    // Rank 0, in the pass over the DEM: the others know and end too.
    std::fprintf(stderr, "aal-bake-mpi: interrupted before any tile\n");
    return aal::kExitFailure;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (progress) progress->finish();
  if (rank == 0 && !o.report.quiet) {
    std::string perRank;
    for (int baked : summary.bakedByRank)
      perRank += (perRank.empty() ? "" : ", ") + std::to_string(baked);
    std::string target = o.output;
    if (o.svf) {
      target += " (sky-view factor: " +
                (std::filesystem::path(o.output) / aal::kSkyViewFactorMosaicName).string() + ")";
    }
    const double texels = static_cast<double>(geometry.texelCount()) * summary.tiles.baked /
                          std::max(1, summary.tiles.tiles);
    // DEM texels the ranks' windows read, per DEM texel.
    double read = 0.0;
    for (uint64_t rankTexels : summary.texelsReadByRank) read += static_cast<double>(rankTexels);
    read /= static_cast<double>(geometry.texelCount());
    std::fprintf(stderr,
                 "aal-bake-mpi: %s %dx%d, %d-texel tiles on %d ranks%s (%d baked: %s per rank; "
                 "%d resumed), %d azimuths, %d threads per rank, in %.2f s (%.3g "
                 "texel-azimuths/s; the pass over the DEM %.2f s; windows of %.3g DEM "
                 "texels read per texel) -> %s\n",
                 tiling.sourceName.c_str(), geometry.width, geometry.height, o.tileSize, ranks,
                 summary.rootBakes ? "" : " (rank 0 only hands out)", summary.tiles.baked,
                 perRank.c_str(), summary.tiles.resumed, o.azimuths, threads, seconds,
                 texels * o.azimuths / seconds, summary.demPassSeconds, read, target.c_str());
  }
  return aal::kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
  // MPI_THREAD_MULTIPLE lets rank 0 bake on one thread while another answers
  // the ranks; without it rank 0 only hands out tiles.
  int threading = MPI_THREAD_SINGLE;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &threading);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);

  CLI::App app(
      "aal-bake's tiled bake across the ranks of an MPI job: mpirun -np N aal-bake-mpi DEM "
      "--tile-size T\n-o FOLDER (or srun under Slurm). The ranks share one read of the DEM (its "
      "checksum and,\nwithout --max-distance, the far field's pyramid, which every rank gets), "
      "then rank 0 hands out\nthe tiles as ranks ask; each rank reads each tile's window of the "
      "DEM "
      "(the tile and its\nhalo, never the whole DEM) and writes its tiles into FOLDER, which every "
      "rank must reach\n(a shared file system). The folder is the same, bit for bit, as aal-bake "
      "--tile-size T\nwrites; a job that died (a killed rank ends the job) resumes from its "
      "finished tiles\nwhen run again, with any number of ranks or with aal-bake. "
      "docs/baking.md.\n\n" +
          aal::demFormatsHelp(),
      "aal-bake-mpi");
  Options o;
  app.add_option("dem", o.dem, "input DEM (every rank reads it)")->required();
  app.add_option("-o,--output", o.output, "output folder of the tiled bake")->required();
  app.add_option("--tile-size", o.tileSize, "tiles of N x N texels")
      ->check(CLI::Range(aal::kMinTileSize, aal::kMaxTileSize))
      ->capture_default_str();
  aal::addSweepOptions(app, o);
  aal::addNearReachOption(app, o);
  app.add_flag("--svf", o.svf,
               "also write the sky-view factor (Zaksek) into the folder: svf_ROW_COL.tif per tile "
               "(float32 GeoTIFF placed like that window of the DEM) and their mosaic "
               "sky_view_factor.vrt, written by rank 0 at the end");
  aal::addGeoTiffOutputOptions(app, o.geotiff, "the --svf tiles", /*formats=*/false);
  app.add_option("--threads", o.threads,
                 "worker threads per rank (default: the host's cores shared among its ranks)")
      ->check(CLI::Range(1, 1024));
  aal::addMapStorageOptions(app, o);
  aal::addProgressOptions(app, o.report);

  aal::installInterruptHandler();
  // Every rank parses the same command line; only rank 0 says what is wrong.
  int code = 0;
  aal::GdalArguments arguments(argc, argv);
  argc = arguments.argc();
  argv = arguments.argv();
  if (rank == 0) {
    code = aal::runToolBody(app, argc, argv, [&] { return run(o); });
  } else {
    try {
      aal::checkFiniteArguments(app, argc, argv);
      app.parse(argc, argv);
      code = run(o);
    } catch (const CLI::ParseError&) {
      code = aal::kExitBadInput;
    } catch (const aal::InputError&) {
      code = aal::kExitBadInput;  // the same on rank 0, which said it
    } catch (const std::exception& e) {
      std::fprintf(stderr, "aal-bake-mpi: rank %d: error: %s\n", rank, e.what());
      code = aal::kExitFailure;
    }
  }
  MPI_Finalize();
  return aal::endTool(code);
}
