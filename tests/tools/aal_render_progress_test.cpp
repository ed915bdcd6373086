// aal-render --progress json: its stages' lines alone on stdout, --stats
// moved to stderr (docs/cli.md, "Progress for scripts").
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "aperture/tests/tools/progress_lines.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::TempDir;

TEST(AalRenderProgress, JsonLinesAloneOnStdoutThroughTheBakeAndTheFrames) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 48, 40);
  const std::string environment = "AAL_FFMPEG= AAL_CACHE_DIR=" + quoted(dir.path() / "cache");
  // A sequence on a fresh cache: the map's bake, then the frames.
  const test::SplitRun sequence = test::runSplit(
      "aal-render", dir,
      quoted(dem) + " -o " + quoted(dir.path() / "day.png") +
          " --size 32x18 --time-range 2024-06-21T12:00Z 2024-06-21T18:00Z --frames 3 "
          "--progress json",
      environment);
  ASSERT_EQ(sequence.exitCode, 0) << sequence.err;
  std::vector<test::JsonLine> parsed;
  for (const std::string& line : test::lines(sequence.out)) {
    test::JsonLine j;
    ASSERT_TRUE(test::parseJsonLine(line, j)) << "not a progress line: '" << line << "'";
    parsed.push_back(j);
  }
  ASSERT_GE(parsed.size(), 4u) << sequence.out;
  EXPECT_EQ(parsed.front().stage, "baking");
  EXPECT_EQ(parsed.front().done, 0u);
  EXPECT_EQ(parsed.back().stage, "rendering");
  EXPECT_EQ(parsed.back().total, 3u);  // frames
  EXPECT_EQ(parsed.back().done, 3u);
  // Each stage's lines: from 0, never back, to its total.
  for (const char* stage : {"baking", "rendering"}) {
    std::vector<test::JsonLine> of;
    for (const test::JsonLine& j : parsed) {
      if (j.stage == stage) of.push_back(j);
    }
    ASSERT_FALSE(of.empty()) << stage;
    EXPECT_EQ(of.front().done, 0u) << stage;
    for (size_t i = 1; i < of.size(); ++i) EXPECT_GE(of[i].done, of[i - 1].done) << stage;
    EXPECT_EQ(of.back().done, of.back().total) << stage;
  }
  EXPECT_NE(sequence.err.find("3 frames in"), std::string::npos) << sequence.err;

  // A still with the map cached: no stage, and --stats on stderr.
  const test::SplitRun still =
      test::runSplit("aal-render", dir,
                     quoted(dem) + " -o " + quoted(dir.path() / "still.png") +
                         " --size 32x18 --stats --progress json",
                     environment);
  ASSERT_EQ(still.exitCode, 0) << still.err;
  EXPECT_EQ(still.out, "");
  EXPECT_NE(still.err.find("triangles"), std::string::npos) << still.err;

  // Without json, --stats stays on stdout.
  const test::SplitRun plain = test::runSplit(
      "aal-render", dir,
      quoted(dem) + " -o " + quoted(dir.path() / "still.png") + " --size 32x18 --stats",
      environment);
  ASSERT_EQ(plain.exitCode, 0) << plain.err;
  EXPECT_NE(plain.out.find("triangles"), std::string::npos) << plain.out;
}

}  // namespace
}  // namespace aal
