// A tiled bake spread over the ranks of an MPI job (aal-bake-mpi,
// docs/baking.md, "Across machines: MPI"): the same folder, bit for bit, as
// the single-process tiled bake (tiled_bake.h). Built only with -DAAL_MPI=ON.
//
// Rank 0 checks the options and takes the folder's lock. The ranks share
// one pass over the DEM (sharedDemPass): each reads its share of the rows,
// hashes them and builds their block rows of the far field's pyramid; the
// row hashes go to rank 0, which makes the checksum, and every rank gets
// every block row. Rank 0 opens the folder (refusing another bake's,
// removing dead temporaries, writing the manifest) and broadcasts the
// checksum. Then it hands the tiles out as ranks ask for them: a rank gets
// the next tile of the tile row whose window it holds, else the first tile
// row nobody started, else a tile of the row with the most left. Each rank
// skips tiles already finished (tileFinished) and bakes and writes the
// others, each from its window of the DEM read through GDAL (the tile and
// tileHalo around it, never the whole DEM), slid along the tile row
// (TileWindowReader: the next tile of the row reads only its new columns).
// Rank 0 bakes too, on a thread of its own beside the one that
// answers the ranks, when MPI gives it MPI_THREAD_MULTIPLE and the job has
// more than one rank. When every tile is done rank 0 writes the SVF mosaic
// (with --svf) and index.txt.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "aperture/preprocess/tiled_bake.h"

namespace aal {

// Another rank failed before the tiles were handed out and has said why;
// this rank ends with `exitCode` (1 or 2) without a message of its own.
class MpiPeerFailed : public std::runtime_error {
 public:
  explicit MpiPeerFailed(int exitCode)
      : std::runtime_error("another rank failed"), exitCode_(exitCode) {}
  int exitCode() const { return exitCode_; }

 private:
  int exitCode_;
};

// This rank failed, or was interrupted, after the tiles were handed out:
// the other ranks would wait for it, so the caller must end the job
// (MPI_Abort with exitCode: 2 for bad input, else 1). what() says why.
class MpiTileFailed : public std::runtime_error {
 public:
  MpiTileFailed(int exitCode, const std::string& what)
      : std::runtime_error(what), exitCode_(exitCode) {}
  int exitCode() const { return exitCode_; }

 private:
  int exitCode_;
};

struct MpiTiledBakeSummary {
  TiledBakeSummary tiles;  // over all ranks
  int ranks = 1;
  bool rootBakes = false;        // rank 0 baked tiles too
  std::vector<int> bakedByRank;  // tiles baked (not resumed) per rank
  // DEM samples each rank's tile windows read (the pass not counted).
  std::vector<uint64_t> texelsReadByRank;
  double demPassSeconds = 0.0;  // the pass over the DEM, with the folder's opening
};

struct MpiTiledBakeHooks {
  // Called on a rank before it bakes tile (row, column), given to it and
  // not found finished: the tests kill the rank there, mid-bake, holding a
  // tile it will never write (aal-bake-mpi's AAL_BAKE_MPI_KILL_AT).
  std::function<void(int row, int column)> beforeTile;
};

// Which rank reads chunk `chunk` of `chunks` in a pass shared by `ranks`.
using DemChunkOwner = std::function<int(int chunk, int chunks, int ranks)>;
// The default: contiguous runs of chunks, as even as they come.
int evenDemChunkOwner(int chunk, int chunks, int ranks);

// How the pass's rows are shared; the tests choose other shares.
struct DemPassShares {
  DemChunkOwner owner = evenDemChunkOwner;
  // Rows per chunk, rounded up to whole block rows of the pyramid; 0:
  // demPassChunkRows.
  int chunkRows = 0;
};

// Collective over `comm`: the pass over the DEM (scanDemForTiledBake's),
// shared. The DEM is read in chunks of demPassChunkRows rows (whole block
// rows of the pyramid); shares.owner says who reads which. Each rank hashes its
// chunks' rows and fills their block rows of the pyramid's finest level;
// the hashes are summed into rank 0, which alone returns the checksum, and
// each chunk's block rows are broadcast from its owner, so that every rank
// returns the whole pyramid (without a max distance; in a file in
// `pyramidFolder`, in memory if that is empty), the same floats as one
// process's pass. bake.cancel is polled between chunks. An error on
// any rank (voids are an InputError; BakeCancelled) is thrown on rank 0,
// the lowest failing rank's, and MpiPeerFailed on the others.
TiledBakeDemPass sharedDemPass(MPI_Comm comm, const DemSource& source, const Heightfield& geometry,
                               const BakeOptions& bake, const TiledBakeOptions& tiled,
                               const DemPassShares& shares = {},
                               const std::string& pyramidFolder = {});

// Collective over `comm`: every rank calls it with the same arguments
// (`geometry` is demGeometry of `source` on every rank). Returns the same
// summary on every rank. Errors before the tiles are handed out (bad
// options, another bake's folder, a busy folder, voids) are thrown on rank
// 0 and MpiPeerFailed on the others; an error or an interrupt while baking
// is thrown as MpiTileFailed on the rank it happened on. bake.progress
// gets 0 during the pass over the DEM (on the ranks that read a part), then
// on rank 0 alone the share of the tiles finished (baked by any rank, or
// found finished) after each, from any of rank 0's threads; a tile's own
// progress is not reported.
// Memory per rank: two windows (4 bytes per texel of the tile and tileHalo
// around it: (3 T + 2 S)^2 for tiles of T and S steps of the near reach or
// max distance, whatever the DEM's width), one tile's sums and the blocks of
// the pyramid its far field reads (FarFieldWindow; the pyramid itself,
// ~0.083 bytes per DEM texel, in a file per rank in
// tiledBakePyramidFolder); during the pass one 64 MB chunk of rows and 8
// bytes per DEM row.
MpiTiledBakeSummary bakeTiledMpi(MPI_Comm comm, const DemSource& source,
                                 const Heightfield& geometry, const BakeOptions& bake,
                                 const TiledBakeOptions& tiled, const std::string& folder,
                                 const MpiTiledBakeHooks& hooks = {});

}  // namespace aal
