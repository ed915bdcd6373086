// One version everywhere: every tool's --version, and the version recorded in
// the files the tools write (aperture maps, tiled-bake folders, GeoTIFFs).
#include <gtest/gtest.h>

#include <gdal_priv.h>

#include <filesystem>
#include <regex>
#include <string>

#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/version.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

TEST(Version, ComesFromTheProjectLineAndTheRevision) {
  EXPECT_TRUE(std::regex_match(versionNumber(), std::regex(R"(\d+\.\d+\.\d+)"))) << versionNumber();
  EXPECT_TRUE(std::regex_match(gitRevision(), std::regex(R"((|[0-9a-f]{7,}))"))) << gitRevision();
  const std::string revision = gitRevision();
  EXPECT_EQ(versionLine("aal-bake"), "aal-bake " + std::string(versionNumber()) +
                                         (revision.empty() ? "" : " (" + revision + ")"));
  EXPECT_EQ(softwareName(), versionLine("aperture"));
}

TEST(Version, EveryToolPrintsItsVersionAndExitsZero) {
  std::vector<std::string> tools = {"aal-bake", "aal-render", "aal-view", "aal-relief",
                                    "aal-info", "aal-caps",   "aal-synth"};
  if (fs::exists(test::binDir() / "aal-bake-mpi")) tools.push_back("aal-bake-mpi");
  for (const std::string& tool : tools) {
    SCOPED_TRACE(tool);
    // Even where a positional argument or an option is required.
    // Open MPI leaks at start-up where a sanitizer build's LeakSanitizer
    // sees it (as tests/tools/aal_bake_mpi_test.cpp runs it too).
    const test::ToolResult result =
        runTool(tool, "--version", tool == "aal-bake-mpi" ? "LSAN_OPTIONS=detect_leaks=0" : "");
    EXPECT_EQ(result.exitCode, 0) << result.out;
    EXPECT_EQ(result.out, versionLine(tool) + "\n");
  }
}

TEST(Version, MapsFoldersAndGeoTiffsRecordWhatWroteThem) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 40, 32);
  const fs::path map = dir.path() / "map.exr";
  const fs::path svf = dir.path() / "svf.tif";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --azimuths 8 --svf " +
                                    quoted(svf) + " -q")
                .exitCode,
            0);
  EXPECT_EQ(ApertureMapReader(map.string()).header().info.software, softwareName());

  ensureGdal();
  GDALDatasetUniquePtr tiff(GDALDataset::Open(svf.string().c_str(), GDAL_OF_RASTER));
  ASSERT_TRUE(tiff);
  const char* software = tiff->GetMetadataItem("TIFFTAG_SOFTWARE");
  ASSERT_NE(software, nullptr);
  EXPECT_EQ(std::string(software), softwareName());

  const fs::path folder = dir.path() / "tiles";
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(folder) +
                                    " --tile-size 16 --azimuths 8 --max-distance 300 -q")
                .exitCode,
            0);
  EXPECT_EQ(readApertureTileIndex(folder.string()).map.info.software, softwareName());
}

}  // namespace
}  // namespace aal
