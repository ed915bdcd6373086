// aal-bake --progress: GDAL's terminal progress and JSON lines on stdout,
// nothing else there, and the modes' names on a bad one (docs/cli.md,
// "Progress for scripts").
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
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

using test::JsonLine;
using test::lines;
using test::parseJsonLine;
using test::SplitRun;

SplitRun bakeSplit(const TempDir& dir, const std::string& arguments) {
  return test::runSplit("aal-bake", dir, arguments);
}

TEST(AalBakeProgress, GdalModePrintsGdalsTermProgressOnStdout) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 64, 64);
  const SplitRun r =
      bakeSplit(dir, quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " --progress=gdal");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // What gdal_translate prints, to the byte: 0, then a dot or a number for
  // every 2.5 %, and the end.
  EXPECT_EQ(r.out, "0...10...20...30...40...50...60...70...80...90...100 - done.\n");
  EXPECT_NE(r.err.find("aal-bake: "), std::string::npos) << r.err;  // the summary stays
}

TEST(AalBakeProgress, JsonModeWritesOnlyParseableLinesThatReachTheTotal) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 128, 128);
  // Long enough (about half a second on one thread) for lines between the
  // first and the last.
  const SplitRun r = bakeSplit(dir, quoted(dem) + " -o " + quoted(dir.path() / "a.exr") +
                                        " --azimuths 1024 --threads 1 --progress json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  ASSERT_FALSE(r.out.empty());
  EXPECT_EQ(r.out.back(), '\n');
  const std::vector<std::string> text = lines(r.out);
  std::vector<JsonLine> parsed;
  for (const std::string& line : text) {
    JsonLine j;
    ASSERT_TRUE(parseJsonLine(line, j)) << "not a progress line: '" << line << "'";
    parsed.push_back(j);
  }
  ASSERT_GE(parsed.size(), 2u);
  EXPECT_EQ(parsed.front().done, 0u);
  for (size_t i = 0; i < parsed.size(); ++i) {
    EXPECT_EQ(parsed[i].stage, "baking");
    EXPECT_EQ(parsed[i].total, parsed.front().total);
    EXPECT_LE(parsed[i].done, parsed[i].total);
    if (i == 0) continue;
    EXPECT_GE(parsed[i].done, parsed[i - 1].done) << text[i];
    EXPECT_GE(parsed[i].seconds, parsed[i - 1].seconds) << text[i];
    // At most ten a second: only the stage's last line may follow sooner.
    if (i + 1 < parsed.size()) {
      EXPECT_GE(parsed[i].seconds - parsed[i - 1].seconds, 0.099) << text[i];
    }
  }
  EXPECT_EQ(parsed.back().done, parsed.back().total);
  EXPECT_NE(r.err.find("aal-bake: "), std::string::npos) << r.err;  // the summary on stderr
}

TEST(AalBakeProgress, QuietJsonKeepsTheLinesAndDropsTheSummary) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 48, 48);
  const SplitRun r =
      bakeSplit(dir, quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " -q --progress json");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<std::string> text = lines(r.out);
  ASSERT_GE(text.size(), 2u) << r.out;
  JsonLine last;
  ASSERT_TRUE(parseJsonLine(text.back(), last)) << text.back();
  EXPECT_EQ(last.done, last.total);
  EXPECT_EQ(r.err, "");
}

TEST(AalBakeProgress, NoneAndBarLeaveStdoutEmpty) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 48, 48);
  for (const char* mode : {"none", "bar"}) {
    const SplitRun r =
        bakeSplit(dir, quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " --progress=" + mode);
    ASSERT_EQ(r.exitCode, 0) << mode << ": " << r.err;
    EXPECT_EQ(r.out, "") << mode;
    EXPECT_NE(r.err.find("aal-bake: "), std::string::npos) << mode << ": " << r.err;
    EXPECT_TRUE(fs::exists(dir.path() / "a.exr")) << mode;
    fs::remove(dir.path() / "a.exr");
  }
}

TEST(AalBakeProgress, AnUnknownModeIsBadUsageNamingTheModes) {
  TempDir dir;
  const fs::path dem = test::writeSyntheticDem(dir, 16, 16);
  const SplitRun r =
      bakeSplit(dir, quoted(dem) + " -o " + quoted(dir.path() / "a.exr") + " --progress=xml");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--progress"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("bar,gdal,json,none"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir.path() / "a.exr"));
}

TEST(JsonLineParser, RefusesWhatIsNotAProgressLine) {
  JsonLine j;
  EXPECT_TRUE(parseJsonLine(R"({"stage":"baking","done":3,"total":10,"seconds":0.5})", j));
  EXPECT_EQ(j.done, 3u);
  EXPECT_EQ(j.total, 10u);
  EXPECT_FALSE(parseJsonLine(R"({"stage":"baking","done":3,"total":10})", j));
  EXPECT_FALSE(parseJsonLine(R"({"stage":"baking","done":3.5,"total":10,"seconds":0.5})", j));
  EXPECT_FALSE(parseJsonLine(R"({"stage":baking,"done":3,"total":10,"seconds":0.5})", j));
  EXPECT_FALSE(parseJsonLine("0...10", j));
}

}  // namespace
}  // namespace aal
