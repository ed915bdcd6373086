// Durable outputs (terrain/io/atomic_file.h): every file a tool writes is
// flushed to its disk (fsync) before it is renamed into place, and its folder
// after the rename, so that a power loss leaves the old file or the whole
// new one behind a name. Seen through a preloaded library that logs each
// fsync and rename in order (sync_log_shim.cpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

// The environment that preloads the logging library (and tells
// AddressSanitizer, where it runs, that it need not come first).
std::string loggedEnvironment(const fs::path& log) {
  return "LD_PRELOAD=" + quoted(AAL_SYNC_LOG_SHIM) + " AAL_SYNC_LOG=" + quoted(log) +
         " ASAN_OPTIONS=\"${ASAN_OPTIONS:-}:verify_asan_link_order=0\"";
}

std::vector<std::string> lines(const fs::path& file) {
  std::vector<std::string> all;
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) all.push_back(line);
  return all;
}

// Checks the log for `output`: a rename of a temporary onto it, preceded by
// an fsync of that temporary and followed by an fsync of its folder.
void expectDurable(const std::vector<std::string>& log, const fs::path& output) {
  std::string suffix = " ";
  suffix.append(output.string());  // not " " + ...: GCC 12's -Wrestrict false alarm
  for (size_t i = 0; i < log.size(); ++i) {
    const std::string& line = log[i];
    if (line.rfind("rename ", 0) != 0 || line.size() < suffix.size() ||
        line.compare(line.size() - suffix.size(), suffix.size(), suffix) != 0) {
      continue;
    }
    const std::string temporary = line.substr(7, line.size() - 7 - suffix.size());
    bool flushedBefore = false, folderAfter = false;
    for (size_t j = 0; j < i; ++j) flushedBefore |= log[j] == "fsync " + temporary;
    for (size_t j = i + 1; j < log.size(); ++j) {
      folderAfter |= log[j] == "fsync " + output.parent_path().string();
    }
    EXPECT_TRUE(flushedBefore) << temporary << " renamed onto " << output << " unflushed";
    EXPECT_TRUE(folderAfter) << "the folder of " << output << " not flushed after its rename";
    return;
  }
  ADD_FAILURE() << "no rename onto " << output << " in the log";
}

TEST(DurableOutput, ABakesMapAndRastersAreFlushedBeforeTheirRenameAndTheirFolderAfter) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 64, 48);
  const fs::path out = fs::canonical(dir.path()) / "out";
  fs::create_directories(out);
  const fs::path log = dir.path() / "sync.log";
  const auto r = runTool("aal-bake",
                         quoted(dem) + " -o " + quoted(out / "map.exr") + " --svf " +
                             quoted(out / "svf.tif") + " --azimuths 8 -q",
                         loggedEnvironment(log));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const std::vector<std::string> logged = lines(log);
  expectDurable(logged, out / "map.exr");
  expectDurable(logged, out / "svf.tif");
}

TEST(DurableOutput, ATiledBakesTilesAndMosaicAreFlushedBeforeTheirRename) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 60, 40);
  const fs::path tiles = fs::canonical(dir.path()) / "tiles";
  const fs::path log = dir.path() / "sync.log";
  const auto r = runTool("aal-bake",
                         quoted(dem) + " -o " + quoted(tiles) +
                             " --tile-size 32 --svf --azimuths 8 --max-distance 200 -q",
                         loggedEnvironment(log));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const std::vector<std::string> logged = lines(log);
  size_t outputs = 0;
  for (const auto& entry : fs::directory_iterator(tiles)) {
    if (!entry.is_regular_file()) continue;
    SCOPED_TRACE(entry.path().filename().string());
    expectDurable(logged, entry.path());
    ++outputs;
  }
  EXPECT_GE(outputs, 5u);  // 2 x 2 tiles, their SVFs, the index and the mosaic
}

TEST(DurableOutput, AReliefIsFlushedBeforeItsRename) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 64, 48);
  const fs::path out = fs::canonical(dir.path()) / "relief.tif";
  const fs::path log = dir.path() / "sync.log";
  const auto r =
      runTool("aal-relief", quoted(dem) + " -o " + quoted(out) + " -q", loggedEnvironment(log));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  expectDurable(lines(log), out);
}

}  // namespace
}  // namespace aal
