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

#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::TempDir;

struct SplitRun {
  int exitCode = -1;
  std::string out, err;
};

std::string fileText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// aal-bake with `arguments`, its stdout and stderr apart.
SplitRun bakeSplit(const TempDir& dir, const std::string& arguments) {
  const fs::path out = dir.path() / "stdout.txt", err = dir.path() / "stderr.txt";
  // Appended, not chained with +: GCC 12 reports a false -Wrestrict.
  std::string command = "(";
  command += (test::binDir() / "aal-bake").string();
  command += " ";
  command += arguments;
  command += " >";
  command += quoted(out);
  command += " 2>";
  command += quoted(err);
  command += ")";
  const test::ToolResult r = test::runShell(command);
  return {r.exitCode, fileText(out), fileText(err)};
}

struct JsonLine {
  std::string stage;
  uint64_t done = 0, total = 0;
  double seconds = 0;
};

// One line of --progress json, read as JSON: an object of exactly the four
// members, in any order, strings and numbers as JSON writes them; false for
// anything else.
bool parseJsonLine(const std::string& line, JsonLine& parsed) {
  static const std::regex member(
      R"re(\s*"(stage|done|total|seconds)"\s*:\s*("[a-z ]*"|-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?)\s*)re");
  if (line.size() < 2 || line.front() != '{' || line.back() != '}') return false;
  std::stringstream body(line.substr(1, line.size() - 2));
  std::string part;
  int seen = 0;
  while (std::getline(body, part, ',')) {
    std::smatch m;
    if (!std::regex_match(part, m, member)) return false;
    const std::string name = m[1], value = m[2];
    if (name == "stage") {
      if (value.front() != '"') return false;
      parsed.stage = value.substr(1, value.size() - 2);
      seen |= 1;
    } else {
      if (value.front() == '"') return false;
      if (name == "seconds") {
        parsed.seconds = std::stod(value);
        seen |= 8;
      } else {
        if (value.find_first_of(".eE-") != std::string::npos) return false;  // counts
        (name == "done" ? parsed.done : parsed.total) = std::stoull(value);
        seen |= name == "done" ? 2 : 4;
      }
    }
  }
  return seen == 15;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
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
