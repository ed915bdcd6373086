// The standard hostile cases, run against every tool they apply to (issue 17):
// numbers that are not finite, outputs that alias inputs or each other, a
// tiny file whose header claims gigabytes, and writes that fail half way
// (a file-size limit, a full disk). Each ends with a clear message, the
// right exit code and nothing left behind.
#include <gtest/gtest.h>

#include <sys/mount.h>
#include <sys/stat.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "aperture/tests/terrain/io/hostile_files.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

const fs::path kDem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";

// Every entry in `folder`, names only: what a failed run must not add to.
std::vector<std::string> entriesOf(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) {
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  return names;
}

struct ToolCase {
  std::string tool, arguments;  // arguments hold kValue where the hostile value goes
};

// Not a plain letter: the temporary folder's random name in the same
// arguments may hold any letter (an 'X' there once took the value).
constexpr const char* kValue = "{value}";

std::string withValue(std::string text, const std::string& value) {
  const size_t at = text.rfind(kValue);
  if (at != std::string::npos) text.replace(at, std::string(kValue).size(), value);
  return text;
}

TEST(HostileInput, NumbersThatAreNotFiniteExitWithTwoInEveryTool) {
  TempDir dir;
  const std::string dem = quoted(kDem), out = quoted(dir.path() / "out");
  const std::vector<ToolCase> cases = {
      {"aal-bake", dem + " -o " + out + ".exr --max-distance {value}"},
      {"aal-render", dem + " -o " + out + ".png --size 32x18 --fov {value}"},
      {"aal-view", dem + " --sun-elevation {value} --sun-azimuth 10"},
      {"aal-caps", "--table " + out + ".csv --max-radius {value}"},
      {"aal-info", dem + " --cell-size {value}"},
      {"aal-synth", "-o " + out + ".tif --amplitude {value}"},
      {"aal-relief", dem + " -o " + out + ".tif --sun-elevation {value}"},
  };
  for (const ToolCase& c : cases) {
    for (const std::string value : {"nan", "inf", "-inf", "1e999", "-NaN"}) {
      const std::string arguments = withValue(c.arguments, value);
      const auto r = runTool(c.tool, arguments);
      EXPECT_EQ(r.exitCode, 2) << c.tool << " " << arguments << "\n" << r.out;
      EXPECT_NE(r.out.find("every number must be finite"), std::string::npos)
          << c.tool << " " << arguments << "\n"
          << r.out;
    }
  }
  // The form --option=value too.
  EXPECT_EQ(runTool("aal-render", dem + " -o " + out + ".png --fov=nan").exitCode, 2);
  EXPECT_TRUE(entriesOf(dir.path()).empty());
}

TEST(HostileInput, RangeErrorsNameTheBoundNotTheTypesLimit) {
  // CLI11's own check printed "not in range 0.000000 to" and DBL_MAX in
  // full: 309 digits.
  for (const std::string& arguments :
       {quoted(kDem) + " -o x.exr --max-distance -5", quoted(kDem) + " -o x.exr --max-distance=inf",
        quoted(kDem) + " -o x.exr --cell-size 0"}) {
    const auto r = runTool("aal-bake", arguments);
    EXPECT_EQ(r.exitCode, 2) << arguments << "\n" << r.out;
    EXPECT_LT(r.out.size(), 200u) << r.out;
    EXPECT_EQ(r.out.find("179769313486231570814527423731704356798070567525844996598917476803157"),
              std::string::npos)
        << r.out;
  }
  EXPECT_NE(runTool("aal-bake", quoted(kDem) + " -o x.exr --max-distance -5")
                .out.find("--max-distance: must be at least 0, got -5"),
            std::string::npos);
}

TEST(HostileInput, OutputsThatAliasInputsOrEachOtherExitWithTwoInEveryTool) {
  TempDir dir;
  const fs::path map = dir.path() / "m.exr", table = dir.path() / "t.png";
  std::ofstream(map, std::ios::binary) << "a map we must not lose";
  const std::vector<ToolCase> cases = {
      {"aal-bake", quoted(kDem) + " -o " + quoted(map) + " --svf " + quoted(map)},
      {"aal-render", quoted(kDem) + " --aperture " + quoted(map) + " -o " + quoted(map)},
      {"aal-view",
       quoted(kDem) + " --aperture " + quoted(map) + " --frames 1 --screenshot " + quoted(map)},
      {"aal-caps", "--table " + quoted(table) + " --plot " + quoted(table)},
      {"aal-relief", quoted(kDem) + " --aperture " + quoted(map) + " -o " + quoted(map)},
  };
  for (const ToolCase& c : cases) {
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.tool << " " << c.arguments << "\n" << r.out;
  }
  EXPECT_EQ(fs::file_size(map), 22u);
  EXPECT_EQ(entriesOf(dir.path()), std::vector<std::string>{"m.exr"});
}

TEST(HostileInput, ATinyFileClaimingAHugeDemIsRefusedAtOnceByEveryTool) {
  TempDir dir;
  const fs::path claims = dir.path() / "claims.tif";
  // 65536 strips of 4096 floats, all at the same bytes: 1 GB claimed by 1 MB.
  std::ofstream(claims, std::ios::binary) << test::sharedStripTiff(4096, 65536);
  const std::string out = quoted(dir.path() / "out");
  const std::vector<ToolCase> cases = {
      {"aal-info", quoted(claims)},
      {"aal-bake", quoted(claims) + " -o " + out + ".exr"},
      {"aal-render", quoted(claims) + " --mode reference --size 32x18 -o " + out + ".png"},
      {"aal-relief", quoted(claims) + " -o " + out + ".tif"},
  };
  for (const ToolCase& c : cases) {
    // Refused at open, before the 1 GB of heights is allocated.
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.tool << "\n" << r.out;
    EXPECT_NE(r.out.find("its blocks claim 1073741824 bytes in all"), std::string::npos)
        << c.tool << "\n"
        << r.out;
  }
  EXPECT_EQ(entriesOf(dir.path()), std::vector<std::string>{"claims.tif"});
}

// Runs `tool` with writes limited to `kilobytes` per file (ulimit -f, with
// SIGXFSZ ignored so that a write past it fails with EFBIG, as on a full disk).
test::ToolResult runWithFileSizeLimit(const std::string& tool, const std::string& arguments,
                                      int kilobytes) {
  return test::runShell("trap '' XFSZ; ulimit -f " + std::to_string(kilobytes) + "; " +
                        (test::binDir() / tool).string() + " " + arguments);
}

TEST(HostileInput, AWriteThatFailsHalfWayExitsWithOneAndLeavesNothing) {
  TempDir dir;
  const fs::path out = dir.path() / "out";
  const std::vector<ToolCase> cases = {
      // A PNG's failed write went unnoticed: exit 0 and a truncated file.
      {"aal-render",
       quoted(kDem) +
           " --mode reference --size 640x360 --reference-sun-rays 1 --reference-sky-rays 1 -q -o " +
           quoted(out) + ".png"},
      {"aal-render",
       quoted(kDem) +
           " --mode reference --size 640x360 --reference-sun-rays 1 --reference-sky-rays 1 -q -o " +
           quoted(out) + ".exr"},
      {"aal-bake", quoted(kDem) + " -q -o " + quoted(out) + ".exr"},
      {"aal-bake", quoted(kDem) + " -q -o " + quoted(out) + ".exr --svf " + quoted(out) + ".tif"},
      {"aal-caps", "--table " + quoted(out) + ".csv"},
      {"aal-synth", "--size 512 -o " + quoted(out) + ".tif"},
  };
  for (const ToolCase& c : cases) {
    const auto r = runWithFileSizeLimit(c.tool, c.arguments, 16);
    EXPECT_EQ(r.exitCode, 1) << c.tool << " " << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find("cannot write"), std::string::npos) << r.out;
    // Named by the output the user gave, not by our temporary.
    EXPECT_EQ(r.out.find(".tmp-"), std::string::npos) << r.out;
    EXPECT_TRUE(entriesOf(dir.path()).empty()) << c.tool << " " << c.arguments << " left "
                                               << ::testing::PrintToString(entriesOf(dir.path()));
  }
}

TEST(HostileInput, AFullDiskIsSaidInPlainWords) {
  TempDir dir;
  const fs::path disk = dir.path() / "disk";
  fs::create_directory(disk);
  if (::mount("tmpfs", disk.c_str(), "tmpfs", 0, "size=64k") != 0) {
    GTEST_SKIP() << "cannot mount a small tmpfs here (" << std::strerror(errno)
                 << "); needs root, as in the CI container";
  }
  const std::vector<ToolCase> cases = {
      {"aal-render",
       quoted(kDem) +
           " --mode reference --size 640x360 --reference-sun-rays 1 --reference-sky-rays 1 -q -o " +
           quoted(disk / "r.png")},
      {"aal-bake", quoted(kDem) + " -q -o " + quoted(disk / "a.exr")},
      {"aal-synth", "--size 512 -o " + quoted(disk / "s.tif")},
      {"aal-caps", "--table " + quoted(disk / "t.csv")},
  };
  for (const ToolCase& c : cases) {
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 1) << c.tool << "\n" << r.out;
    std::string lower = r.out;
    for (char& ch : lower) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    EXPECT_NE(lower.find("no space left on device"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find(".tmp-"), std::string::npos) << r.out;
    EXPECT_TRUE(entriesOf(disk).empty()) << ::testing::PrintToString(entriesOf(disk));
  }
  ::umount(disk.c_str());
}

TEST(HostileInput, MistakesOfUseExitWithTwo) {
  TempDir dir;
  const fs::path one = dir.path() / "one.asc";
  std::ofstream(one) << "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 5\n7\n";
  const std::string png = " --size 32x18 -o " + quoted(dir.path() / "r.png");
  struct Case {
    std::string tool, arguments, message;
  };
  for (const Case& c : std::vector<Case>{
           {"aal-render", quoted(one) + png,
            "1 x 1 texels have no surface to render; rendering needs at least 2 x 2"},
           {"aal-render", quoted(kDem) + png + " --camera 100,100,500 --look-at 100,100,500",
            "--camera and --look-at are the same point"},
           {"aal-render", quoted(kDem) + png + " --device 9", "--device 9 is not available"},
           {"aal-caps", "--table " + quoted(dir.path() / "t.csv") + " --plot p.txt",
            "--plot p.txt must end in .png"},
       }) {
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.tool << " " << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << r.out;
  }
  EXPECT_EQ(entriesOf(dir.path()), std::vector<std::string>{"one.asc"});
}

// Writes go to regular files only: `-o /dev/null` (as root) replaced the
// device node with a regular file, and so would a link to it or a FIFO.
// Here through links and a FIFO in a temporary folder, which a tool that
// got it wrong could only replace there; /dev itself is checked without
// writing (AtomicOutput.DevicesFifosAndSystemFoldersAreNoOutputs).
TEST(HostileInput, OutputsThatAreNotFilesAreRefusedInEveryTool) {
  TempDir dir;
  for (const char* extension : {".png", ".exr", ".tif", ".csv"}) {
    fs::create_symlink("/dev/null", dir.path() / (std::string("null") + extension));
  }
  fs::create_symlink("/dev/stdout", dir.path() / "stdout.csv");
  for (const char* name : {"pipe.png", "pipe.tif"}) {
    ASSERT_EQ(::mkfifo((dir.path() / name).c_str(), 0644), 0);
  }
  const fs::path folder = dir.path() / "tiles";
  fs::create_directory(folder);
  ASSERT_EQ(::mkfifo((folder / "index.txt").c_str(), 0644), 0);
  const std::vector<std::string> before = entriesOf(dir.path());
  const auto at = [&](const std::string& name) { return quoted(dir.path() / name); };
  const std::string device = "(a link to /dev/null) is a character device, not a file";
  const std::string fifo = "is a FIFO (a pipe), not a file";
  struct Case {
    std::string tool, arguments, message;
  };
  for (const Case& c : std::vector<Case>{
           {"aal-render", quoted(kDem) + " --size 32x18 -o " + at("null.png"), device},
           {"aal-render", quoted(kDem) + " --size 32x18 -o " + at("pipe.png"), fifo},
           {"aal-bake", quoted(kDem) + " -o " + at("null.exr"), device},
           {"aal-bake", quoted(kDem) + " -o " + at("m.exr") + " --svf " + at("pipe.tif"), fifo},
           {"aal-bake", quoted(kDem) + " --tile-size 16 -o " + quoted(folder), fifo},
           {"aal-relief", quoted(kDem) + " -o " + at("null.tif"), device},
           {"aal-synth", "--size 8 -o " + at("pipe.tif"), fifo},
           {"aal-caps", "--table " + at("null.csv"), device},
           // A pipe or a terminal, as the test runs: never a file.
           {"aal-caps", "--table " + at("stdout.csv"), ", not a file"},
           {"aal-caps", "--table " + at("t.csv") + " --plot " + at("pipe.png"), fifo},
           {"aal-view", quoted(kDem) + " --frames 1 --screenshot " + at("null.png"), device},
       }) {
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.tool << " " << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.tool << " " << c.arguments << "\n"
                                                        << r.out;
    EXPECT_NE(r.out.find("give the path of a file"), std::string::npos) << r.out;
  }
  EXPECT_EQ(entriesOf(dir.path()), before);
  EXPECT_EQ(entriesOf(folder), std::vector<std::string>{"index.txt"});
  for (const char* extension : {".png", ".exr", ".tif", ".csv"}) {
    EXPECT_TRUE(fs::is_symlink(dir.path() / (std::string("null") + extension))) << extension;
  }
  EXPECT_TRUE(fs::is_symlink(dir.path() / "stdout.csv"));
  EXPECT_TRUE(fs::is_fifo(dir.path() / "pipe.png"));
  EXPECT_TRUE(fs::is_fifo(dir.path() / "pipe.tif"));
  EXPECT_TRUE(fs::is_fifo(folder / "index.txt"));
  EXPECT_TRUE(fs::is_character_file("/dev/null"));
}

}  // namespace
}  // namespace aal
