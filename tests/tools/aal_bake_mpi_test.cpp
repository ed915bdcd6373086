// aal-bake-mpi (built with -DAAL_MPI=ON): three ranks under mpirun write the
// folder aal-bake's tiled bake writes, byte for byte, and a job whose rank
// was killed finishes the same folder when run again.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "aperture/terrain/io/aperture_map.h"
#include "aperture/tests/tools/progress_lines.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::folderContents;
using test::quoted;
using test::runShell;
using test::runTool;
using test::TempDir;

fs::path writeDem(const TempDir& dir, int width, int height) {
  return test::writeSyntheticDem(dir, width, height, 3);
}

// Every bake here stamps its EXRs with the same capDate (aperture_map.cpp):
// two bakes a second apart are otherwise not the same bytes.
const std::string kFixedDate = "SOURCE_DATE_EPOCH=1700000000";

// aal-bake with kFixedDate.
test::ToolResult runBake(const std::string& arguments) {
  return runTool("aal-bake", arguments, kFixedDate);
}

// mpirun with `ranks` ranks on this machine, more ranks than cores allowed.
// The tests run as root here and in CI, which mpirun refuses unless told;
// the sanitizer build's LD_PRELOAD is for aal-view, not mpirun (its own
// runtime is linked into aal-bake-mpi). Under the sanitizer build the ranks
// check addresses and undefined behaviour but not leaks: Open MPI's plugins
// leave allocations behind and are unloaded before LeakSanitizer reports,
// so no suppression can name them (the bake's own code is leak-checked
// through aal-bake's tests).
test::ToolResult runMpi(int ranks, const std::string& arguments,
                        const std::string& environment = "") {
  return runShell(
      "env -u LD_PRELOAD LSAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 "
      "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
      kFixedDate + " " + environment + " " + quoted(AAL_TEST_MPIEXEC) + " -np " +
      std::to_string(ranks) + " --oversubscribe --bind-to none " +
      quoted(test::binDir() / "aal-bake-mpi") + " " + arguments);
}

bool hasTemporaries(const fs::path& folder) {
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.path().filename().string().find(".tmp-") != std::string::npos) return true;
  }
  return false;
}

// 150 x 120 texels in tiles of 32: 5 x 4 tiles, more than the ranks, so
// that every rank asks again and rows are shared.
TEST(AalBakeMpi, ThreeRanksWriteTheSingleProcessFolderByteForByte) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 150, 120);
  // The far field (no max distance; its default reach and a longer one: the
  // shortest the far field takes, 128 cells, already covers this DEM, so the
  // library's tests hold the windows that are part of the rows and columns
  // under the far field), and a distance-limited bake with the clamped edge,
  // curvature and full floats (partial windows); two with the sky-view
  // factor (its GeoTIFFs and VRT too).
  for (const std::string options :
       {" --tile-size 32 --azimuths 16 --svf", " --tile-size 32 --azimuths 8 --near-reach 3900",
        " --tile-size 32 --azimuths 8 --max-distance 300 --edge clamp --curvature --float "
        "--svf"}) {
    SCOPED_TRACE(options);
    const fs::path single = dir.path() / "single", mpi = dir.path() / "mpi";
    fs::remove_all(single);
    fs::remove_all(mpi);
    const auto s = runBake(quoted(dem) + " -o " + quoted(single) + options + " -q");
    ASSERT_EQ(s.exitCode, 0) << s.out;
    const auto m = runMpi(3, quoted(dem) + " -o " + quoted(mpi) + options);
    ASSERT_EQ(m.exitCode, 0) << m.out;
    EXPECT_NE(m.out.find("on 3 ranks (20 baked"), std::string::npos) << m.out;
    const test::FolderContents want = folderContents(single), have = folderContents(mpi);
    // 20 tiles, index, manifest (the lock goes with the bake); with --svf 20
    // GeoTIFFs and the VRT.
    const bool svf = options.find("--svf") != std::string::npos;
    EXPECT_EQ(have.size(), svf ? 43u : 22u);
    EXPECT_FALSE(have.count(".aal-bake.lock"));
    EXPECT_TRUE(have.count("index.txt"));
    EXPECT_EQ(have.count("sky_view_factor.vrt"), svf ? 1u : 0u);
    if (options.find("--near-reach") != std::string::npos) {
      EXPECT_NE(have.at("index.txt").find("reach 3900 m"), std::string::npos);
    }
    for (const auto& [name, bytes] : want) {
      ASSERT_TRUE(have.count(name)) << name;
      EXPECT_TRUE(have.at(name) == bytes) << name << " differs";
    }
    EXPECT_EQ(have.size(), want.size());
  }
  // The ranks' shared pass records the checksum aal-bake's in-memory bake
  // writes (version 2, the row hash).
  const fs::path one = dir.path() / "one.exr";
  ASSERT_EQ(runBake(quoted(dem) + " -o " + quoted(one) + " --azimuths 8 -q").exitCode, 0);
  const std::string checksum = ApertureMapReader(one.string()).header().info.sourceChecksum;
  EXPECT_EQ(checksum.rfind(kRowHashChecksumPrefix, 0), 0u) << checksum;
  EXPECT_EQ(readApertureTileIndex((dir.path() / "mpi").string()).map.info.sourceChecksum, checksum);
}

// Rank 0 reports the share of the tiles finished, whichever rank baked
// them: --progress json's lines on stdout go from 0 to the whole in steps
// of whole tiles (20 tiles: 50 thousandths each), never back; a tile's own
// progress is not mixed in. Run again on the finished folder, every tile
// counts as finished.
TEST(AalBakeMpi, RankZeroReportsTheTilesFinishedByEveryRank) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 150, 120);
  const fs::path mpi = dir.path() / "mpi", lines = dir.path() / "progress.txt";
  for (const char* run : {"bakes", "resumes"}) {
    SCOPED_TRACE(run);
    const auto m =
        runMpi(3, quoted(dem) + " -o " + quoted(mpi) +
                      " --tile-size 32 --azimuths 8 --progress json -q >" + quoted(lines));
    ASSERT_EQ(m.exitCode, 0) << m.out;
    std::istringstream text(test::fileText(lines));
    std::vector<test::JsonLine> reports;
    for (std::string line; std::getline(text, line);) {
      test::JsonLine j;
      ASSERT_TRUE(test::parseJsonLine(line, j)) << "not a progress line: '" << line << "'";
      reports.push_back(j);
    }
    ASSERT_GE(reports.size(), 2u);
    EXPECT_EQ(reports.front().done, 0u);
    EXPECT_EQ(reports.back().done, reports.back().total);
    for (size_t i = 0; i < reports.size(); ++i) {
      EXPECT_EQ(reports[i].stage, "baking");
      EXPECT_EQ(reports[i].total, 1000u);
      EXPECT_EQ(reports[i].done % 50, 0u) << reports[i].done;
      if (i > 0) {
        EXPECT_GE(reports[i].done, reports[i - 1].done);
      }
    }
  }
}

// A rank killed with SIGKILL holding a tile ends the job (Open MPI aborts
// it); the finished tiles stay, and the same command finishes the folder,
// equal byte for byte to the single-process bake. So does aal-bake, also for
// a tile whose SVF GeoTIFF is missing. (The rank given tile (2, 2) dies,
// whichever it is: on a loaded machine which rank bakes how many tiles
// varies.)
TEST(AalBakeMpi, AKilledRankEndsTheJobAndRunningAgainFinishesTheFolder) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 150, 120);
  // With the SVF: a tile is finished with its GeoTIFF, and the VRT comes at the end.
  const std::string options = " --tile-size 32 --azimuths 16 --svf";
  const fs::path single = dir.path() / "single", mpi = dir.path() / "mpi";
  ASSERT_EQ(runBake(quoted(dem) + " -o " + quoted(single) + options + " -q").exitCode, 0);
  const std::string command = quoted(dem) + " -o " + quoted(mpi) + options;
  const auto killed = runMpi(3, command, "AAL_BAKE_MPI_KILL_AT=2,2");
  EXPECT_NE(killed.exitCode, 0) << killed.out;
  ASSERT_TRUE(fs::is_directory(mpi)) << killed.out;
  EXPECT_FALSE(fs::exists(mpi / "index.txt"));
  EXPECT_FALSE(fs::exists(mpi / "sky_view_factor.vrt"));
  int tiles = 0;
  for (const auto& [name, bytes] : folderContents(mpi)) tiles += name.rfind("tile_", 0) == 0;
  EXPECT_FALSE(fs::exists(mpi / apertureTileName(2, 2)));
  EXPECT_LT(tiles, 20);

  const auto resumed = runMpi(2, command);
  ASSERT_EQ(resumed.exitCode, 0) << resumed.out;
  EXPECT_NE(resumed.out.find(std::to_string(tiles) + " resumed)"), std::string::npos)
      << resumed.out;
  EXPECT_FALSE(hasTemporaries(mpi));
  EXPECT_TRUE(folderContents(mpi) == folderContents(single));

  // A folder the MPI bake left unfinished is aal-bake's to finish too.
  fs::remove(mpi / "index.txt");
  fs::remove(mpi / apertureTileName(2, 3));
  fs::remove(mpi / "svf_0001_0004.tif");
  const auto plain = runBake(quoted(dem) + " -o " + quoted(mpi) + options);
  ASSERT_EQ(plain.exitCode, 0) << plain.out;
  EXPECT_NE(plain.out.find("(2 baked, 18 resumed)"), std::string::npos) << plain.out;
  EXPECT_TRUE(folderContents(mpi) == folderContents(single));
}

// Bad input is said once, by rank 0, and every rank exits with 2; a folder
// of another bake is left as it was.
TEST(AalBakeMpi, BadInputIsSaidOnceAndExitsWithTwo) {
  TempDir dir;
  const auto missing = runMpi(
      2, quoted(dir.path() / "none.tif") + " -o " + quoted(dir.path() / "out") + " --tile-size 32");
  EXPECT_EQ(missing.exitCode, 2) << missing.out;
  const size_t first = missing.out.find("none.tif");
  ASSERT_NE(first, std::string::npos) << missing.out;
  EXPECT_EQ(missing.out.find("aal-bake-mpi", missing.out.find("aal-bake-mpi") + 1),
            std::string::npos)
      << missing.out;

  const fs::path dem = writeDem(dir, 70, 50), folder = dir.path() / "other";
  ASSERT_EQ(
      runBake(quoted(dem) + " -o " + quoted(folder) + " --tile-size 32 --azimuths 8 -q").exitCode,
      0);
  const test::FolderContents before = folderContents(folder);
  const auto other =
      runMpi(2, quoted(dem) + " -o " + quoted(folder) + " --tile-size 16 --azimuths 8");
  EXPECT_EQ(other.exitCode, 2) << other.out;
  EXPECT_NE(other.out.find("in tiles of 32, not 16"), std::string::npos) << other.out;
  EXPECT_TRUE(folderContents(folder) == before);
}

// As aal-bake: a DEM in the folder under a name the bake writes
// (svf_0000_0000.tif) would be overwritten; refused once, before any work,
// the folder as it was.
TEST(AalBakeMpi, AnInputNamedLikeTheFoldersFilesIsRefusedBeforeAnyWork) {
  TempDir dir;
  const fs::path folder = dir.path() / "tiles";
  fs::create_directory(folder);
  fs::copy_file(writeDem(dir, 40, 40), folder / "svf_0000_0000.tif");
  const test::FolderContents before = folderContents(folder);
  const auto inside = runMpi(
      2, quoted(folder / "svf_0000_0000.tif") + " -o " + quoted(folder) + " --tile-size 16 --svf");
  EXPECT_EQ(inside.exitCode, 2) << inside.out;
  EXPECT_NE(inside.out.find("-o " + folder.string() +
                            " writes the tiled bake's files (tile_ROW_COL.exr, svf_ROW_COL.tif"),
            std::string::npos)
      << inside.out;
  EXPECT_NE(inside.out.find("and the input DEM (" + (folder / "svf_0000_0000.tif").string() +
                            ") is one of them"),
            std::string::npos)
      << inside.out;
  EXPECT_EQ(inside.out.find("aal-bake-mpi", inside.out.find("aal-bake-mpi") + 1), std::string::npos)
      << inside.out;
  EXPECT_TRUE(folderContents(folder) == before);
}

// As aal-bake: a near reach below the far field's minimum is refused, said
// once, before any work.
TEST(AalBakeMpi, ANearReachBelowTheFarFieldsMinimumIsRefusedOnce) {
  TempDir dir;
  const fs::path dem = writeDem(dir, 40, 40), folder = dir.path() / "tiles";
  const auto reach =
      runMpi(2, quoted(dem) + " -o " + quoted(folder) + " --tile-size 16 --near-reach 1");
  EXPECT_EQ(reach.exitCode, 2) << reach.out;
  EXPECT_NE(reach.out.find("--near-reach 1 m is shorter than the far field allows: at least "
                           "480 m"),
            std::string::npos)
      << reach.out;
  EXPECT_EQ(reach.out.find("aal-bake-mpi", reach.out.find("aal-bake-mpi") + 1), std::string::npos)
      << reach.out;
  EXPECT_FALSE(fs::exists(folder));
}

}  // namespace
}  // namespace aal
