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

// `tool` with `arguments` (shell syntax), ended after 10 s: a run that
// blocks (on a FIFO) exits 124 and fails the test instead of hanging it.
// `environment` ("NAME=value ...") is set for the run.
test::ToolResult runWithin10s(const std::string& tool, const std::string& arguments,
                              const fs::path& folder = {}, const std::string& environment = "") {
  return test::runShell((folder.empty() ? "" : "cd " + quoted(folder) + " && ") + "timeout 10 " +
                        (environment.empty() ? "" : "env " + environment + " ") +
                        quoted(test::binDir() / tool) + " " + arguments);
}

// A small DEM for aal-render's GPU path, whose aperture map is baked (in
// milliseconds) into a cache beside it: albedo images are read there only,
// after the map (the reference renderer takes a constant albedo).
struct SmallRender {
  TempDir work;
  fs::path dem = work.path() / "small.tif";
  std::string environment = "AAL_CACHE_DIR=" + quoted(work.path() / "cache");
  SmallRender() {
    const auto r = runTool("aal-synth", "-o " + quoted(dem) + " --size 32");
    EXPECT_EQ(r.exitCode, 0) << r.out;
  }
};

// Paths reach GDAL as files: a connection string (MEM:::DATAPOINTER=...
// made GDAL read memory at the address given: SIGSEGV), another driver's
// prefix or a /vsi path but /vsicurl/, /vsizip/ and /vsigzip/ is refused
// with exit 2 by every tool that reads a DEM, and for --water-mask; a file
// that has such a name is read as the file.
TEST(HostileInput, GdalConnectionStringsExitWithTwoInEveryTool) {
  TempDir dir;
  const std::string out = quoted(dir.path() / "out");
  const std::string mem = "'MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10'";
  const std::vector<ToolCase> cases = {
      {"aal-info", "{value}"},
      {"aal-bake", "{value} -o " + out + ".exr"},
      {"aal-render", "{value} --mode reference --size 32x18 -o " + out + ".png"},
      {"aal-relief", "{value} -o " + out + ".tif"},
      {"aal-relief", quoted(kDem) + " -o " + out + ".tif --water-mask {value}"},
  };
  for (const ToolCase& c : cases) {
    // Every tool with MEM:::, aal-info with the others too.
    for (const std::string& value :
         {mem, std::string("NUMPY:::0x1"), std::string("/vsimem/dem.tif")}) {
      if (value != mem && c.tool != "aal-info") continue;
      const std::string arguments = withValue(c.arguments, value);
      const auto r = runWithin10s(c.tool, arguments);
      EXPECT_EQ(r.exitCode, 2) << c.tool << " " << arguments << "\n" << r.out;
      EXPECT_NE(r.out.find(value == mem ? "MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10: is a GDAL "
                                          "connection string (MEM:...), not a file"
                                        : "not a file: aperture opens files"),
                std::string::npos)
          << c.tool << " " << arguments << "\n"
          << r.out;
    }
  }
  EXPECT_TRUE(entriesOf(dir.path()).empty());
  // The DEM under a name GDAL would take for a connection string.
  fs::copy_file(kDem, dir.path() / "MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10");
  const auto r = runWithin10s("aal-info", mem, dir.path());
  EXPECT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("GTiff"), std::string::npos) << r.out;
}

// What is not a file is refused for what it is, never opened: a FIFO (whose
// open blocked for ever), a device (/dev/zero read without end), a symbolic
// link loop (said to be "no such file"), as a DEM, a water mask, an
// aperture map, an albedo image, a colour ramp or a camera path (horizons:
// HorizonMap.FilesThatAreNotFilesAreRefusedUnopened).
TEST(HostileInput, InputsThatAreNotFilesExitWithTwoAndNeverBlock) {
  TempDir dir;
  const fs::path fifo = dir.path() / "fifo", loop = dir.path() / "loop";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  fs::create_symlink(dir.path() / "loop2", loop);
  fs::create_symlink(loop, dir.path() / "loop2");
  const std::string dem = quoted(kDem), out = quoted(dir.path() / "out");
  const std::string png = " --size 32x18 -o " + out + ".png";
  const SmallRender small;
  const std::vector<ToolCase> cases = {
      {"aal-info", "{value}"},
      {"aal-bake", "{value} -o " + out + ".exr"},
      {"aal-render", "{value} --mode reference" + png},
      {"aal-relief", "{value} -o " + out + ".tif"},
      {"aal-relief", dem + " -o " + out + ".tif --water-mask {value}"},
      {"aal-relief", dem + " -o " + out + ".tif --aperture {value}"},
      {"aal-relief", dem + " -o " + out + ".tif --color-relief {value}"},
      {"aal-render", dem + " --aperture {value}" + png},
      {"aal-render", quoted(small.dem) + " --albedo {value}" + png},
      {"aal-render", dem + " --camera-path {value} --frames 2" + png},
  };
  struct Value {
    fs::path path;
    std::string says;
  };
  for (const ToolCase& c : cases) {
    // A FIFO everywhere; a device and a loop as a DEM and as a ramp.
    for (const Value& v : {Value{fifo, "is a FIFO, not a file"},
                           Value{"/dev/zero", "is a character device, not a file"},
                           Value{loop, "is a symbolic link loop"}}) {
      if (v.path != fifo && c.tool != "aal-info" &&
          c.arguments.find("--color-relief") == std::string::npos) {
        continue;
      }
      const std::string arguments = withValue(c.arguments, quoted(v.path));
      const auto r = runWithin10s(c.tool, arguments, {}, small.environment);
      EXPECT_EQ(r.exitCode, 2) << c.tool << " " << arguments << "\n" << r.out;
      EXPECT_NE(r.out.find(v.path.string()), std::string::npos)
          << c.tool << " " << arguments << "\n"
          << r.out;
      EXPECT_NE(r.out.find(v.says), std::string::npos) << c.tool << " " << arguments << "\n"
                                                       << r.out;
    }
  }
  EXPECT_EQ(entriesOf(dir.path()), (std::vector<std::string>{"fifo", "loop", "loop2"}));
}

// An albedo image whose header claims 20000 x 20000 pixels over a few bytes
// is refused from its header, before any pixel is decoded, exit 2.
TEST(HostileInput, AnAlbedoImageClaimingAHugeSizeIsRefusedFromItsHeader) {
  TempDir dir;
  const fs::path albedo = dir.path() / "claims.png";
  std::ofstream(albedo, std::ios::binary) << test::rgbPngClaiming(20000, 20000);
  const SmallRender small;
  const auto r = runWithin10s("aal-render",
                              quoted(small.dem) + " --albedo " + quoted(albedo) +
                                  " --size 32x18 -o " + quoted(dir.path() / "out.png"),
                              {}, small.environment);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("claims.png is truncated or corrupt: its header declares 20000 x 20000 "
                       "pixels"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(entriesOf(dir.path()), std::vector<std::string>{"claims.png"});
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

}  // namespace
}  // namespace aal
