#include "aperture/preprocess/mpi_tiled_bake.h"

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "aperture/preprocess/sky_view_factor_tiles.h"
#include "aperture/preprocess/tile_window_reader.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/heightfield_checksum.h"

namespace aal {

namespace {

constexpr int kRequestTag = 1;  // rank -> 0: {outcome of its last tile, its window's tile row}
constexpr int kAssignTag = 2;   // 0 -> rank: {tile row, column}, or {-1, -1}: no more
constexpr int kFailureTag = 3;  // rank -> 0: why it failed before the handout
constexpr int kNoOutcome = 0, kBaked = 1, kResumed = 2;

// Waits for `request` without spinning: Open MPI's blocking calls poll at
// full speed, and a rank waiting for rank 0's pass over the DEM (minutes at
// scale) or for another rank's last tile would take a core from the ranks
// still baking on its node.
void waitPolitely(MPI_Request& request, MPI_Status* status = MPI_STATUS_IGNORE) {
  for (;;) {
    int done = 0;
    MPI_Test(&request, &done, status);
    if (done) return;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void broadcastPolitely(void* data, int count, MPI_Datatype type, MPI_Comm comm) {
  MPI_Request request;
  MPI_Ibcast(data, count, type, 0, comm, &request);
  waitPolitely(request);
}

// MPI counts are ints: the block rows of a chunk of a DEM a million columns
// wide may hold more floats.
void broadcastFloats(float* data, size_t count, int root, MPI_Comm comm) {
  constexpr size_t kChunk = size_t{1} << 28;
  for (size_t first = 0; first < count; first += kChunk) {
    MPI_Bcast(data + first, static_cast<int>(std::min(kChunk, count - first)), MPI_FLOAT, root,
              comm);
  }
}

// How a step before the handout ended on a rank: 0, an exit code (1 or 2),
// or kInterrupted.
constexpr int kInterrupted = 3;

int statusOf(const std::exception_ptr& error) {
  if (!error) return 0;
  try {
    std::rethrow_exception(error);
  } catch (const BakeCancelled&) {
    return kInterrupted;
  } catch (const InputError&) {
    return 2;
  } catch (...) {
    return 1;
  }
}

std::string messageOf(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown error";
  }
}

// Every rank's outcome of a step before the handout, agreed on. When a rank
// failed, the lowest such rank's error is thrown on rank 0, which says it
// (once for the job), and MpiPeerFailed on the others.
void agreeBeforeHandout(MPI_Comm comm, int rank, int ranks, const std::exception_ptr& error) {
  int first = error ? rank : ranks;
  MPI_Request request;
  MPI_Iallreduce(MPI_IN_PLACE, &first, 1, MPI_INT, MPI_MIN, comm, &request);
  waitPolitely(request);
  if (first == ranks) return;
  int status = rank == first ? statusOf(error) : 0;
  std::string message = rank == first ? messageOf(error) : std::string();
  if (first != 0 && rank == first) {
    MPI_Send(&status, 1, MPI_INT, 0, kFailureTag, comm);
    MPI_Send(message.data(), static_cast<int>(message.size()), MPI_CHAR, 0, kFailureTag, comm);
  } else if (first != 0 && rank == 0) {
    MPI_Recv(&status, 1, MPI_INT, first, kFailureTag, comm, MPI_STATUS_IGNORE);
    MPI_Status probe;
    MPI_Probe(first, kFailureTag, comm, &probe);
    int length = 0;
    MPI_Get_count(&probe, MPI_CHAR, &length);
    message.resize(static_cast<size_t>(length));
    MPI_Recv(message.data(), length, MPI_CHAR, first, kFailureTag, comm, MPI_STATUS_IGNORE);
  }
  broadcastPolitely(&status, 1, MPI_INT, comm);
  if (rank != 0) throw MpiPeerFailed(status == kInterrupted ? 1 : status);
  if (first == 0) std::rethrow_exception(error);
  if (status == kInterrupted) throw BakeCancelled();
  if (status == 2) throw InputError(message);  // a void, say: the DEM's fault, not the rank's
  throw std::runtime_error("rank " + std::to_string(first) + ": " + message);
}

// The tiles not yet handed out. A rank is given the next tile of the tile
// row whose window it holds (only new columns read), else the first row
// nobody started, else a tile of the row with the most left.
class TileDispenser {
 public:
  TileDispenser(int rows, int columns)
      : columns_(columns), nextColumn_(static_cast<size_t>(rows), 0) {}

  std::optional<std::pair<int, int>> next(int bandRow) {
    const std::lock_guard<std::mutex> guard(mutex_);
    const int rows = static_cast<int>(nextColumn_.size());
    int row = -1;
    if (bandRow >= 0 && bandRow < rows && nextColumn_[bandRow] < columns_) {
      row = bandRow;
    } else {
      while (firstUnstarted_ < rows && nextColumn_[firstUnstarted_] > 0) ++firstUnstarted_;
      if (firstUnstarted_ < rows) {
        row = firstUnstarted_;
      } else {
        int most = 0;
        for (int r = 0; r < rows; ++r) {
          if (columns_ - nextColumn_[r] > most) most = columns_ - nextColumn_[r], row = r;
        }
      }
    }
    if (row < 0) return std::nullopt;
    return std::pair{row, nextColumn_[row]++};
  }

 private:
  std::mutex mutex_;
  int columns_;
  std::vector<int> nextColumn_;
  int firstUnstarted_ = 0;
};

// What the ranks did, as rank 0 hears it; with `progress`, the share of
// the `tiles` finished (baked or resumed) after each.
class Tally {
 public:
  Tally(int ranks, int tiles, std::function<void(double)> progress)
      : baked_(static_cast<size_t>(ranks), 0), tiles_(tiles), progress_(std::move(progress)) {}
  void add(int rank, int outcome) {
    const std::lock_guard<std::mutex> guard(mutex_);
    if (outcome == kBaked) ++baked_[static_cast<size_t>(rank)];
    if (outcome == kResumed) ++resumed_;
    if (outcome != kNoOutcome && progress_) {
      const int finished = std::accumulate(baked_.begin(), baked_.end(), resumed_);
      progress_(static_cast<double>(finished) / std::max(tiles_, 1));
    }
  }
  const std::vector<int>& baked() const { return baked_; }
  int resumed() const { return resumed_; }

 private:
  std::mutex mutex_;
  std::vector<int> baked_;
  int resumed_ = 0;
  const int tiles_;
  const std::function<void(double)> progress_;
};

// One rank's tiles: skips the finished ones, bakes the others from their
// windows of the DEM (TileWindowReader), slid along a tile row while its
// tiles stay in that row. A tile's own progress is not reported: rank 0
// reports the tiles finished (Tally).
class TileWorker {
 public:
  TileWorker(const DemSource& source, const Heightfield& geometry, const ApertureTileIndex& index,
             const FarField* far, const BakeOptions& bake, const TiledBakeOptions& tiled,
             const std::string& folder, const MpiTiledBakeHooks& hooks)
      : index_(index),
        far_(far),
        bake_(withoutProgress(bake)),
        tiled_(tiled),
        folder_(folder),
        hooks_(hooks),
        reader_(source, geometry, tileHalo(geometry, bake, tiled)) {}

  // kBaked or kResumed.
  int work(int row, int column) {
    if (tileFinished(index_, folder_, row, column)) return kResumed;
    if (hooks_.beforeTile) hooks_.beforeTile(row, column);
    const HeightWindow& window = reader_.windowFor(tileWindow(index_, row, column));
    bandRow_ = row;
    bakeTileInto(window, far_, index_, bake_, tiled_, folder_, row, column);
    return kBaked;
  }
  // The tile row of the window held (-1: none): its next tile reads only
  // the columns it does not share.
  int bandRow() const { return bandRow_; }
  uint64_t texelsRead() const { return reader_.texelsRead(); }

 private:
  static BakeOptions withoutProgress(BakeOptions bake) {
    bake.progress = nullptr;
    return bake;
  }

  const ApertureTileIndex& index_;
  const FarField* far_;
  const BakeOptions bake_;
  const TiledBakeOptions& tiled_;
  const std::string& folder_;
  const MpiTiledBakeHooks& hooks_;
  TileWindowReader reader_;
  int bandRow_ = -1;
};

// Rank 0's side of the handout: answers every other rank until each has
// been told there is no more.
void answerRanks(MPI_Comm comm, int ranks, TileDispenser& dispenser, Tally& tally) {
  for (int active = ranks - 1; active > 0;) {
    int message[2];
    MPI_Request request;
    MPI_Status status;
    MPI_Irecv(message, 2, MPI_INT, MPI_ANY_SOURCE, kRequestTag, comm, &request);
    waitPolitely(request, &status);
    tally.add(status.MPI_SOURCE, message[0]);
    const std::optional<std::pair<int, int>> tile = dispenser.next(message[1]);
    int reply[2] = {-1, -1};
    if (tile) {
      reply[0] = tile->first;
      reply[1] = tile->second;
    } else {
      --active;
    }
    MPI_Send(reply, 2, MPI_INT, status.MPI_SOURCE, kAssignTag, comm);
  }
}

// A rank's side: asks rank 0 for tiles until there are none.
void askForTiles(MPI_Comm comm, TileWorker& worker) {
  int outcome = kNoOutcome;
  for (;;) {
    int message[2] = {outcome, worker.bandRow()};
    MPI_Send(message, 2, MPI_INT, 0, kRequestTag, comm);
    int tile[2];
    MPI_Request request;
    MPI_Irecv(tile, 2, MPI_INT, 0, kAssignTag, comm, &request);
    waitPolitely(request);
    if (tile[0] < 0) return;
    outcome = worker.work(tile[0], tile[1]);
  }
}

// The tile phase: rank 0 hands the tiles out (and bakes), the others bake
// what they are given. On rank 0 `counts` gets the tally, and `progress`
// the share of tiles finished after each.
void handOutAndBake(MPI_Comm comm, int rank, int ranks, const ApertureTileIndex& index,
                    const std::string& folder, TileWorker& worker, std::vector<int>& counts,
                    const std::function<void(double)>& progress) {
  if (rank != 0) {
    askForTiles(comm, worker);
    return;
  }
  // Shared with the answering thread, which outlives this call when the
  // bake here fails (detached; the job is then aborted).
  const auto dispenser = std::make_shared<TileDispenser>(index.rows(), index.columns());
  const auto tally = std::make_shared<Tally>(ranks, index.rows() * index.columns(), progress);
  int threading = MPI_THREAD_SINGLE;
  MPI_Query_thread(&threading);
  const bool rootBakes = ranks == 1 || threading == MPI_THREAD_MULTIPLE;
  if (rootBakes) {
    std::thread answering;
    if (ranks > 1) {
      answering = std::thread(
          [comm, ranks, dispenser, tally] { answerRanks(comm, ranks, *dispenser, *tally); });
    }
    try {
      while (const std::optional<std::pair<int, int>> tile = dispenser->next(worker.bandRow())) {
        tally->add(0, worker.work(tile->first, tile->second));
      }
    } catch (...) {
      // The caller ends the job; the thread waits for ranks that will not ask.
      if (answering.joinable()) answering.detach();
      throw;
    }
    if (answering.joinable()) answering.join();
  } else {
    answerRanks(comm, ranks, *dispenser, *tally);
  }
  // Every rank has asked again after its last tile: all are written.
  finishTileFolder(folder, index);
  std::copy(tally->baked().begin(), tally->baked().end(), counts.begin());
  counts[static_cast<size_t>(ranks)] = tally->resumed();
  counts[static_cast<size_t>(ranks) + 1] = rootBakes ? 1 : 0;
}

}  // namespace

int evenDemChunkOwner(int chunk, int chunks, int ranks) {
  // Rank r reads chunks [r * chunks / ranks, (r + 1) * chunks / ranks).
  return static_cast<int>((static_cast<int64_t>(chunk + 1) * ranks - 1) / chunks);
}

TiledBakeDemPass sharedDemPass(MPI_Comm comm, const DemSource& source, const Heightfield& geometry,
                               const BakeOptions& bake, const TiledBakeOptions& tiled,
                               const DemPassShares& shares, const std::string& pyramidFolder) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  TiledBakeDemPass pass;
  pass.pyramid = emptyTiledBakePyramid(geometry, bake, tiled, pyramidFolder);
  HeightPyramid* pyramid = pass.pyramid ? &*pass.pyramid : nullptr;
  const int blockTexels = pyramid ? 1 << pyramid->baseShift() : 1;
  const int chunkRows = shares.chunkRows > 0
                            ? std::min(geometry.height, (shares.chunkRows + blockTexels - 1) /
                                                            blockTexels * blockTexels)
                            : demPassChunkRows(geometry, pyramid);
  const int chunks = (geometry.height + chunkRows - 1) / chunkRows;
  const auto rowsOf = [&](int chunk) {
    return std::min(chunkRows, geometry.height - chunk * chunkRows);
  };

  // This rank's chunks: their rows' hashes (0 for the others' rows) and
  // their block rows of the pyramid.
  std::vector<uint64_t> rowHashes(static_cast<size_t>(geometry.height), 0);
  std::vector<int> owners(static_cast<size_t>(chunks));
  std::exception_ptr error;
  try {
    for (int chunk = 0; chunk < chunks; ++chunk) {
      owners[static_cast<size_t>(chunk)] = shares.owner(chunk, chunks, ranks);
      if (owners[static_cast<size_t>(chunk)] < 0 || owners[static_cast<size_t>(chunk)] >= ranks) {
        throw std::invalid_argument("pass over the DEM: chunk " + std::to_string(chunk) +
                                    " has no rank");
      }
    }
    for (int chunk = 0; chunk < chunks; ++chunk) {
      if (owners[static_cast<size_t>(chunk)] != rank) continue;
      scanDemChunk(source, geometry, chunk * chunkRows, rowsOf(chunk), rowHashes.data(), pyramid);
      if (bake.progress) bake.progress(0.0);
      if (bake.cancel && bake.cancel->load(std::memory_order_relaxed)) throw BakeCancelled();
    }
  } catch (...) {
    error = std::current_exception();
  }
  agreeBeforeHandout(comm, rank, ranks, error);

  // Each row's hash is on one rank, 0 on the others: their sum is the hash.
  MPI_Request request;
  MPI_Ireduce(rank == 0 ? MPI_IN_PLACE : rowHashes.data(), rowHashes.data(), geometry.height,
              MPI_UINT64_T, MPI_SUM, 0, comm, &request);
  waitPolitely(request);
  if (rank == 0) pass.checksum = rowHashChecksum(geometry.width, geometry.height, rowHashes.data());

  // Every chunk's block rows from its owner to the others.
  if (pyramid) {
    const int shift = pyramid->baseShift();
    const int width = pyramid->level(shift).width;
    std::vector<float> max;  // one chunk's block rows
    for (int chunk = 0; chunk < chunks; ++chunk) {
      const int from = owners[static_cast<size_t>(chunk)];
      const int firstBlockRow = (chunk * chunkRows) >> shift;
      const int blockRows = ((rowsOf(chunk) - 1) >> shift) + 1;
      max.resize(static_cast<size_t>(blockRows) * width);
      if (rank == from) pyramid->readBlocks(shift, 0, firstBlockRow, width, blockRows, max.data());
      broadcastFloats(max.data(), max.size(), from, comm);
      if (rank != from) pyramid->setBaseBlockRows(firstBlockRow, blockRows, max.data());
    }
  }
  return pass;
}

MpiTiledBakeSummary bakeTiledMpi(MPI_Comm comm, const DemSource& source,
                                 const Heightfield& geometry, const BakeOptions& bake,
                                 const TiledBakeOptions& tiled, const std::string& folder,
                                 const MpiTiledBakeHooks& hooks) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  // Rank 0 swept the folder's dead temporaries before any rank writes; a
  // sweep at every write would take a live rank on another host for dead.
  setRemoveDeadTemporariesOnWrite(false);

  // Rank 0 checks the options and locks an existing folder before any rank
  // reads the DEM (a busy folder fails at once); a new folder is made and
  // locked after the pass (a refused DEM leaves no folder).
  const auto start = std::chrono::steady_clock::now();
  std::optional<TiledBakeLock> lock;
  std::exception_ptr error;
  namespace fs = std::filesystem;
  if (rank == 0) {
    try {
      checkTiledBakeOptions(bake, tiled);
      checkSkyViewFactorTiles(geometry, bake.skyViewFactor);
      if (!tiled.lock && fs::is_directory(folder)) lock.emplace(folder);
    } catch (...) {
      error = std::current_exception();
    }
  }
  agreeBeforeHandout(comm, rank, ranks, error);

  // Every rank: its share of the pass; the whole pyramid.
  TiledBakeDemPass pass =
      sharedDemPass(comm, source, geometry, bake, tiled, {}, tiledBakePyramidFolder(tiled, folder));
  const bool farField = !(bake.maxDistanceM > 0.0);

  // Rank 0: the folder, then the checksum to every rank.
  if (rank == 0) {
    try {
      createTileFolder(folder);
      if (!tiled.lock && !lock) lock.emplace(folder);
      pass.checksum = tiledBakeChecksum(folder, pass.checksum,
                                        [&] { return legacyDemChecksum(source, geometry); });
      openTileFolder(folder, tiledBakeIndex(geometry, pass.checksum, bake, tiled));
    } catch (...) {
      error = std::current_exception();
    }
  }
  agreeBeforeHandout(comm, rank, ranks, error);
  char checksum[64] = {};
  if (rank == 0) std::strncpy(checksum, pass.checksum.c_str(), sizeof checksum - 1);
  broadcastPolitely(checksum, sizeof checksum, MPI_CHAR, comm);
  MpiTiledBakeSummary summary;
  summary.ranks = ranks;
  summary.demPassSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const ApertureTileIndex index = tiledBakeIndex(geometry, checksum, bake, tiled);
  const FarField far{pass.pyramid ? &*pass.pyramid : nullptr, resolvedFarField(geometry, tiled)};
  TileWorker worker(source, geometry, index, farField ? &far : nullptr, bake, tiled, folder, hooks);
  summary.tiles.tiles = index.rows() * index.columns();

  // Baked per rank, then resumed, then whether rank 0 baked.
  std::vector<int> counts(static_cast<size_t>(ranks) + 2, 0);
  try {
    handOutAndBake(comm, rank, ranks, index, folder, worker, counts, bake.progress);
  } catch (const BakeCancelled&) {
    throw MpiTileFailed(1, "interrupted; the finished tiles are kept in " + folder +
                               ": run the same command again to resume");
  } catch (const InputError& e) {
    throw MpiTileFailed(2, e.what());
  } catch (const std::exception& e) {
    throw MpiTileFailed(1, std::string("error: ") + e.what());
  }
  broadcastPolitely(counts.data(), static_cast<int>(counts.size()), MPI_INT, comm);
  // Every rank is here once the counts arrive: this gather does not wait.
  const uint64_t texelsRead = worker.texelsRead();
  summary.texelsReadByRank.assign(static_cast<size_t>(ranks), 0);
  MPI_Allgather(&texelsRead, 1, MPI_UINT64_T, summary.texelsReadByRank.data(), 1, MPI_UINT64_T,
                comm);
  summary.bakedByRank.assign(counts.begin(), counts.begin() + ranks);
  for (int baked : summary.bakedByRank) summary.tiles.baked += baked;
  summary.tiles.resumed = counts[static_cast<size_t>(ranks)];
  summary.rootBakes = counts[static_cast<size_t>(ranks) + 1] != 0;
  return summary;
}

}  // namespace aal
