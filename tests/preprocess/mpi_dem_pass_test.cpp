// The pass over the DEM shared by the ranks of an MPI bake (sharedDemPass,
// -DAAL_MPI=ON), run by ctest under mpirun with 3 ranks: whatever rows each
// rank reads, every rank ends with the pyramid HeightPyramid builds from
// the whole DEM (exact floats) and rank 0 with the whole DEM's checksum; a
// void in another rank's rows is rank 0's InputError. And the bake across
// the ranks: rank 0 hears of every tile finished.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <mutex>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aperture/preprocess/height_pyramid.h"
#include "aperture/preprocess/mpi_tiled_bake.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/io/heightfield_checksum.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;

int rankOf(MPI_Comm comm = MPI_COMM_WORLD) {
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

// A folder rank 0 makes and every rank names.
class SharedDir {
 public:
  SharedDir() {
    char path[4096] = {};
    if (rankOf() == 0) {
      dir_.emplace();
      std::snprintf(path, sizeof path, "%s", dir_->path().c_str());
    }
    MPI_Bcast(path, sizeof path, MPI_CHAR, 0, MPI_COMM_WORLD);
    path_ = path;
  }
  ~SharedDir() { MPI_Barrier(MPI_COMM_WORLD); }  // every rank done before rank 0 removes it
  const fs::path& path() const { return path_; }

 private:
  std::optional<test::TempDir> dir_;
  fs::path path_;
};

// 150 x 123 fBm (30 m cells) as a GeoTIFF written by rank 0; `voidRow`: a
// row with one NaN (a void), or -1.
fs::path writeDem(const SharedDir& dir, int voidRow = -1) {
  const fs::path path = dir.path() / "dem.tif";
  if (rankOf() == 0) {
    SyntheticTerrainOptions s;
    s.width = 150;
    s.height = 123;
    s.cellSizeM = 30;
    s.seed = 4;
    s.featureSizeTexels = 24;
    Heightfield field = makeSyntheticTerrain(s);
    if (voidRow >= 0) field.z[field.index(70, voidRow)] = std::numeric_limits<float>::quiet_NaN();
    writeFloatGeoTiff(path.string(), s.width, s.height, field.z.data(),
                      test::testGeoReference(false));
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return path;
}

struct Dem {
  explicit Dem(const fs::path& path)
      : source(path.string(), load), geometry(demGeometry(source, load)) {}
  DemLoadOptions load;
  DemSource source;
  Heightfield geometry;
};

TEST(MpiDemPass, AnySharesGiveTheWholeDemsPyramidAndChecksum) {
  const SharedDir dir;
  const Dem dem(writeDem(dir));
  Heightfield whole = dem.geometry;
  whole.z = readDemRows(dem.source, dem.geometry, 0, dem.geometry.height).z;
  BakeOptions bake;
  bake.azimuths = 8;
  TiledBakeOptions tiled;
  tiled.tileSize = 32;
  // The default near reach: blocks of 8 rows, of which 123 is no multiple.
  const int shift = tiledBakePyramidShift(dem.geometry, tiled);
  ASSERT_EQ(shift, 3);
  const HeightPyramid want = buildHeightPyramid(whole, shift);
  const std::vector<std::pair<std::string, DemChunkOwner>> owners = {
      {"even", evenDemChunkOwner},
      {"round robin", [](int chunk, int, int ranks) { return chunk % ranks; }},
      {"all on the last rank", [](int, int, int ranks) { return ranks - 1; }},
      {"one chunk on rank 0, the rest on rank 1",
       [](int chunk, int, int ranks) { return chunk == 0 || ranks == 1 ? 0 : 1; }},
  };
  int passes = 0;
  for (const auto& [name, owner] : owners) {
    for (int chunkRows : {1, 5, 64, 0}) {
      // Every other pass keeps its pyramid in a file, as aal-bake-mpi does.
      const std::string folder =
          ++passes % 2 == 0 ? std::filesystem::temp_directory_path().string() : std::string();
      SCOPED_TRACE(name + ", chunks of " + std::to_string(chunkRows) + " rows, pyramid in '" +
                   folder + "'");
      const TiledBakeDemPass pass = sharedDemPass(MPI_COMM_WORLD, dem.source, dem.geometry, bake,
                                                  tiled, {owner, chunkRows}, folder);
      EXPECT_EQ(pass.pyramid->inFile(), !folder.empty());
      ASSERT_TRUE(pass.pyramid);
      ASSERT_TRUE(pass.pyramid->complete());
      ASSERT_EQ(pass.pyramid->baseShift(), shift);
      ASSERT_EQ(pass.pyramid->coarsestShift(), want.coarsestShift());
      for (int s = want.baseShift(); s <= want.coarsestShift(); ++s) {
        EXPECT_EQ(pass.pyramid->levelMax(s), want.levelMax(s)) << "shift " << s;
      }
      if (rankOf() == 0) {
        EXPECT_EQ(pass.checksum, heightfieldChecksum(whole));
      }
    }
  }
  // With a max distance: the checksum alone.
  bake.maxDistanceM = 300;
  const TiledBakeDemPass limited =
      sharedDemPass(MPI_COMM_WORLD, dem.source, dem.geometry, bake, tiled,
                    {[](int chunk, int, int ranks) { return (chunk * 7) % ranks; }, 3});
  EXPECT_FALSE(limited.pyramid);
  if (rankOf() == 0) {
    EXPECT_EQ(limited.checksum, heightfieldChecksum(whole));
  }
}

// A void in the last rows (the last rank's under even shares) is said by
// rank 0 as the InputError a single process gives; the others end quietly
// with exit code 2.
TEST(MpiDemPass, AVoidInAnyRanksRowsIsRankZerosInputError) {
  const SharedDir dir;
  const Dem dem(writeDem(dir, 120));
  BakeOptions bake;
  TiledBakeOptions tiled;
  tiled.tileSize = 32;
  try {
    sharedDemPass(MPI_COMM_WORLD, dem.source, dem.geometry, bake, tiled, {evenDemChunkOwner, 8});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(rankOf(), 0);
    EXPECT_NE(std::string(e.what()).find("has voids"), std::string::npos) << e.what();
  } catch (const MpiPeerFailed& e) {
    EXPECT_NE(rankOf(), 0);
    EXPECT_EQ(e.exitCode(), 2);
  }
}

// The whole bake across the ranks: rank 0's bake.progress hears of every
// tile finished, whichever rank baked it, one tile at a time (k of the
// tiles, k = 1, 2, ... in order: a tile's own progress is not mixed in); the
// other ranks hear only the pass's zeros.
TEST(MpiTiledBake, RankZeroHearsEveryTileFinishedOnce) {
  const SharedDir dir;
  const Dem dem(writeDem(dir));
  std::mutex mutex;
  std::vector<double> heard;
  BakeOptions bake;
  bake.azimuths = 6;  // a tile's own passes would report thirds
  bake.progress = [&](double fraction) {
    const std::lock_guard<std::mutex> guard(mutex);
    if (fraction > 0.0) heard.push_back(fraction);
  };
  TiledBakeOptions tiled;
  tiled.tileSize = 32;  // 5 x 4 tiles
  const MpiTiledBakeSummary summary = bakeTiledMpi(MPI_COMM_WORLD, dem.source, dem.geometry, bake,
                                                   tiled, (dir.path() / "tiles").string());
  ASSERT_EQ(summary.tiles.tiles, 20);
  EXPECT_EQ(summary.tiles.baked, 20);
  if (rankOf() != 0) {
    EXPECT_TRUE(heard.empty());
    return;
  }
  ASSERT_EQ(heard.size(), 20u);
  for (size_t k = 0; k < heard.size(); ++k) EXPECT_EQ(heard[k], (k + 1) / 20.0) << k;
}

}  // namespace
}  // namespace aal

// Every rank runs every test (they are collective); the job fails when a
// test fails on any rank (each rank prints its report).
int main(int argc, char** argv) {
  int threading = MPI_THREAD_SINGLE;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &threading);
  testing::InitGoogleTest(&argc, argv);
  int failed = RUN_ALL_TESTS() != 0 ? 1 : 0;
  MPI_Allreduce(MPI_IN_PLACE, &failed, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return failed;
}
