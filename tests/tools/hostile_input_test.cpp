// The standard hostile cases, run against every tool they apply to:
// numbers that are not finite, outputs that alias inputs or each other, a
// tiny file whose header claims gigabytes, and writes that fail half way
// (a file-size limit, a full disk). Each ends with a clear message, the
// right exit code and nothing left behind.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/terrain/io/hostile_files.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/synthetic_dem_file.h"

extern char** environ;

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::FolderContents;
using test::quoted;
using test::runTool;
using test::TempDir;

// The bytes of a file ("" when it is missing): what a refused run must
// leave as it was.
std::string bytesOf(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A width x height fBm DEM (a float GeoTIFF, whatever the name says: GDAL
// reads it by its content) of `cellM` cells at `path`.
void writeDemAt(const fs::path& path, int width, int height, double cellM = 30, uint64_t seed = 1) {
  SyntheticTerrainOptions s;
  s.seed = seed;
  s.width = width;
  s.height = height;
  s.cellSizeM = cellM;
  s.featureSizeTexels = 12;
  const Heightfield field = makeSyntheticTerrain(s);
  GeoReference geo = test::testGeoReference(false);
  geo.stepX = geo.stepY = cellM;
  writeFloatGeoTiff(path.string(), width, height, field.z.data(), geo);
}

// A VRT of one raster, `source` (a path relative to the VRT's folder), of
// width x height.
void writeVrt(const fs::path& path, const std::string& source, int width, int height) {
  std::ofstream(path) << "<VRTDataset rasterXSize=\"" << width << "\" rasterYSize=\"" << height
                      << "\">\n  <GeoTransform>500000, 30, 0, 4000000, 0, -30</GeoTransform>\n"
                      << "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n    <SimpleSource>\n"
                      << "      <SourceFilename relativeToVRT=\"1\">" << source
                      << "</SourceFilename>\n      <SourceBand>1</SourceBand>\n"
                      << "    </SimpleSource>\n  </VRTRasterBand>\n</VRTDataset>\n";
}

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

// aal-render's sequences write OUT-0001.png ... and OUT.mp4: a DEM, camera
// path, albedo, aperture map or horizons file of such a name was
// overwritten. Refused before any work (the bake cache stays empty), the
// input intact.
TEST(HostileInput, SequenceFramesAndTheirMovieNeverOverwriteAnInput) {
  TempDir dir;
  const fs::path cache = dir.path() / "cache";
  const std::string environment = "AAL_CACHE_DIR=" + quoted(cache);
  const std::string out = " -o " + quoted(dir.path() / "out.png") + " --size 32x18 -q ";
  const std::string range = " --time-range 2024-06-21T12:00Z 2024-06-21T14:00Z --frames 3";
  const std::string frames = "-o " + (dir.path() / "out.png").string() +
                             " writes the frames out-0001.png .. out-0003.png into " +
                             dir.path().string() + ", and";
  // A DEM named like a frame; a camera path, an albedo, an aperture map and
  // horizons (their contents never read: the paths are refused first).
  writeDemAt(dir.path() / "out-0002.png", 24, 24);
  std::ofstream(dir.path() / "out-0001.png")
      << "0 -2000 -2000 900 0 0 300\n1 2000 -2000 900 0 0 300\n";
  for (const char* name : {"out-0003.png", "out.mp4"}) std::ofstream(dir.path() / name) << name;
  const auto at = [&](const std::string& name) { return quoted(dir.path() / name); };
  // ffmpeg, as far as the run can tell (AAL_FFMPEG): the movie is written.
  const fs::path ffmpeg = dir.path() / "ffmpeg";
  std::ofstream(ffmpeg) << "#!/bin/sh\nexit 0\n";
  fs::permissions(ffmpeg, fs::perms::owner_all);
  struct Case {
    std::string arguments, environment, message;
  };
  for (const Case& c : std::vector<Case>{
           {at("out-0002.png") + out + range, "", frames + " the input DEM ("},
           {quoted(kDem) + out + "--camera-path " + at("out-0001.png") + " --frames 3", "",
            frames + " the input --camera-path ("},
           {quoted(kDem) + out + "--albedo " + at("out-0003.png") + range, "",
            frames + " the input --albedo ("},
           {quoted(kDem) + out + "--aperture " + at("out-0001.png") + range, "",
            frames + " the input --aperture ("},
           {quoted(kDem) + out + "--horizons " + at("out-0003.png") + range, "",
            frames + " the input --horizons ("},
           {quoted(kDem) + out + "--camera-path " + at("out.mp4") + " --frames 2",
            "AAL_FFMPEG=" + quoted(ffmpeg),
            "out.mp4 (the movie of the frames) is the input --camera-path"},
       }) {
    const auto r = runTool("aal-render", c.arguments, environment + " " + c.environment);
    EXPECT_EQ(r.exitCode, 2) << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find(c.message), std::string::npos) << c.arguments << "\n" << r.out;
  }
  // Five digits: out-00002.png would be frame 2 of 10000.
  fs::copy_file(dir.path() / "out-0002.png", dir.path() / "out-00002.png");
  const auto many = runTool("aal-render",
                            at("out-00002.png") + out +
                                " --time-range 2024-06-21T12:00Z 2024-06-22T12:00Z --frames 10000",
                            environment);
  EXPECT_EQ(many.exitCode, 2) << many.out;
  EXPECT_NE(many.out.find("the frames out-00001.png .. out-10000.png into " + dir.path().string() +
                          ", and the input DEM"),
            std::string::npos)
      << many.out;
  // A frame's name taken by a folder failed after the frames before it.
  fs::create_directory(dir.path() / "seq-0002.png");
  const auto folder =
      runTool("aal-render", quoted(kDem) + " -o " + at("seq.png") + " --size 32x18 -q" + range,
              environment);
  EXPECT_EQ(folder.exitCode, 2) << folder.out;
  EXPECT_NE(folder.out.find("seq-0002.png is a folder, not a file"), std::string::npos)
      << folder.out;
  EXPECT_FALSE(fs::exists(dir.path() / "seq-0001.png"));
  EXPECT_FALSE(fs::exists(cache)) << "refused only after baking";
  EXPECT_EQ(bytesOf(dir.path() / "out-0001.png"),
            "0 -2000 -2000 900 0 0 300\n1 2000 -2000 900 0 0 300\n");
  EXPECT_EQ(bytesOf(dir.path() / "out-0003.png"), "out-0003.png");
  EXPECT_EQ(bytesOf(dir.path() / "out.mp4"), "out.mp4");
  EXPECT_EQ(bytesOf(dir.path() / "out-0002.png"), bytesOf(dir.path() / "out-00002.png"));
  EXPECT_EQ(entriesOf(dir.path()),
            (std::vector<std::string>{"ffmpeg", "out-00002.png", "out-0001.png", "out-0002.png",
                                      "out-0003.png", "out.mp4", "seq-0002.png"}));
}

// --compare DIR writes DIR/reference.png, reference.exr, errors.csv and
// MODE.png, MODE-error.png for every mode: an input of such a name there was
// overwritten. The names come from the writer's own list.
TEST(HostileInput, ComparisonFilesNeverOverwriteAnInput) {
  TempDir dir;
  const fs::path cmp = dir.path() / "cmp";
  fs::create_directory(cmp);
  for (const char* name : {"approx.png", "reference.exr", "baseline-ao-error.png",
                           "approx-without-w.png", "horizon-b.png"}) {
    writeDemAt(cmp / name, 24, 24);
  }
  for (const char* name : {"errors.csv", "exact.png", "a.horizons", "b.horizons"}) {
    std::ofstream(cmp / name) << name;
  }
  const FolderContents before = test::folderContents(cmp);
  const std::string compare = " --size 32x18 -q --compare " + quoted(cmp);
  const auto at = [&](const std::string& name) { return quoted(cmp / name); };
  for (const auto& [arguments, message] : std::vector<std::pair<std::string, std::string>>{
           {at("approx.png") + compare, "approx.png (written by --compare"},
           {at("reference.exr") + compare, "reference.exr (written by --compare"},
           {at("baseline-ao-error.png") + compare, "baseline-ao-error.png (written by --compare"},
           {at("approx-without-w.png") + compare, "approx-without-w.png (written by --compare"},
           {quoted(kDem) + compare + " --horizons " + at("errors.csv"),
            "errors.csv (written by --compare " + cmp.string() + ") is the input --horizons"},
           {quoted(kDem) + compare + " --aperture " + at("exact.png"), "is the input --aperture"},
           // Several horizon maps: one horizon-STEM mode for each.
           {at("horizon-b.png") + compare + " --horizons " + at("a.horizons") + " --horizons " +
                at("b.horizons"),
            "horizon-b.png (written by --compare"},
       }) {
    const auto r = runTool("aal-render", arguments, "AAL_CACHE_DIR=" + quoted(dir.path() / "c"));
    EXPECT_EQ(r.exitCode, 2) << arguments << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << arguments << "\n" << r.out;
  }
  // A file where the folder should be failed after the whole comparison.
  const auto file =
      runTool("aal-render", quoted(kDem) + " --size 32x18 -q --compare " + at("errors.csv"));
  EXPECT_EQ(file.exitCode, 2) << file.out;
  EXPECT_NE(file.out.find("is a file: --compare names a folder"), std::string::npos) << file.out;
  EXPECT_TRUE(test::changedFiles(before, test::folderContents(cmp)).empty())
      << ::testing::PrintToString(test::changedFiles(before, test::folderContents(cmp)));
  EXPECT_FALSE(fs::exists(dir.path() / "c"));
}

// A tiled bake writes tile_ROW_COL.exr, svf_ROW_COL.tif, sky_view_factor.vrt,
// index.txt, manifest.txt and its lock into its folder: a DEM of such a
// name there (or a VRT's source) was overwritten, and the refused run left
// the lock behind. Now refused before any work, the folder as it was.
TEST(HostileInput, ATiledBakeNeverOverwritesAnInputInItsFolder) {
  TempDir dir;
  const fs::path tiles = dir.path() / "tiles";
  fs::create_directory(tiles);
  for (const char* name :
       {"svf_0000_0000.tif", "tile_0001_0000.exr", "index.txt", "sky_view_factor.vrt"}) {
    writeDemAt(tiles / name, 40, 40);
  }
  writeVrt(dir.path() / "d.vrt", "tiles/svf_0000_0000.tif", 40, 40);
  const FolderContents before = test::folderContents(tiles);
  const std::string out = " --tile-size 16 --azimuths 4 --svf -q -o " + quoted(tiles);
  for (const auto& [dem, message] : std::vector<std::pair<fs::path, std::string>>{
           {tiles / "svf_0000_0000.tif", "and the input DEM (" + (tiles / "svf").string()},
           {tiles / "tile_0001_0000.exr", "and the input DEM (" + (tiles / "tile_").string()},
           {tiles / "index.txt", "and the input DEM (" + (tiles / "index.txt").string()},
           {tiles / "sky_view_factor.vrt", "and the input DEM (" + (tiles / "sky_").string()},
           {dir.path() / "d.vrt", "a file GDAL reads for " + (dir.path() / "d.vrt").string()},
       }) {
    const auto r = runTool("aal-bake", quoted(dem) + out);
    EXPECT_EQ(r.exitCode, 2) << dem << "\n" << r.out;
    EXPECT_NE(r.out.find("-o " + tiles.string() +
                         " writes the tiled bake's files (tile_ROW_COL.exr, svf_ROW_COL.tif, "
                         "sky_view_factor.vrt, index.txt, manifest.txt, .aal-bake.lock) into it"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("move the input or choose another output"), std::string::npos) << r.out;
  }
  EXPECT_TRUE(test::changedFiles(before, test::folderContents(tiles)).empty())
      << ::testing::PrintToString(test::changedFiles(before, test::folderContents(tiles)));
}

// Writing a GeoTIFF that a DEM's VRT reads replaced the DEM's data: the
// inputs are every file GDAL reads for a raster (a VRT's sources, nested
// VRTs' too), in every tool that writes.
TEST(HostileInput, AnOutputOverAVrtSourceIsRefused) {
  TempDir dir;
  writeDemAt(dir.path() / "src.tif", 24, 24);
  writeDemAt(dir.path() / "pic.png", 24, 24);
  writeVrt(dir.path() / "d.vrt", "src.tif", 24, 24);
  writeVrt(dir.path() / "outer.vrt", "d.vrt", 24, 24);
  writeVrt(dir.path() / "p.vrt", "pic.png", 24, 24);
  const FolderContents before = test::folderContents(dir.path());
  const auto at = [&](const std::string& name) { return quoted(dir.path() / name); };
  const std::string source = "is the input DEM (" + (dir.path() / "src.tif").string() +
                             ", a file GDAL reads for " + (dir.path() / "d.vrt").string() + ")";
  for (const ToolCase& c : std::vector<ToolCase>{
           {"aal-relief", at("d.vrt") + " -o " + at("src.tif")},
           {"aal-relief", at("outer.vrt") + " -o " + at("src.tif")},
           {"aal-relief", quoted(kDem) + " --water-mask " + at("d.vrt") + " -o " + at("src.tif")},
           {"aal-bake", at("d.vrt") + " -o " + at("m.exr") + " --svf " + at("src.tif")},
           {"aal-render", at("p.vrt") + " --size 32x18 -o " + at("pic.png")},
           {"aal-view", at("p.vrt") + " --frames 1 --screenshot " + at("pic.png")},
           {"aal-view",
            quoted(kDem) + " --drop " + at("p.vrt") + " --frames 1 --screenshot " + at("pic.png")},
       }) {
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.tool << " " << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find("a file GDAL reads for"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("writing it would destroy it; choose another output"), std::string::npos)
        << r.out;
  }
  EXPECT_NE(runTool("aal-relief", at("d.vrt") + " -o " + at("src.tif")).out.find(source),
            std::string::npos);
  EXPECT_TRUE(test::changedFiles(before, test::folderContents(dir.path())).empty())
      << ::testing::PrintToString(test::changedFiles(before, test::folderContents(dir.path())));
}

// Every write sweeps its folder of the temporaries of dead processes
// (.NAME.tmp-PID-N.EXT): an input of such a name there went with them.
TEST(HostileInput, AnInputNamedLikeATemporaryIsNotSweptAway) {
  TempDir dir;
  const fs::path dem = dir.path() / (".dem.tmp-" + std::to_string(test::deadPid()) + "-0.tif");
  writeDemAt(dem, 24, 24);
  const std::string bytes = bytesOf(dem);
  const auto r = runTool("aal-relief", quoted(dem) + " -q -o " + quoted(dir.path() / "r.tif"));
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("is named like a temporary file"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rename the input"), std::string::npos) << r.out;
  EXPECT_EQ(bytesOf(dem), bytes);
  EXPECT_EQ(entriesOf(dir.path()), std::vector<std::string>{dem.filename().string()});
}

// A bake refused after it took the folder's lock (here for --method rays,
// which a tiled bake cannot take) left .aal-bake.lock in the user's folder.
// A bake leaves no lock file, refused or finished.
TEST(HostileInput, ABakeLeavesNoLockFileBehind) {
  TempDir dir;
  const fs::path tiles = dir.path() / "tiles", dem = dir.path() / "d.tif";
  fs::create_directory(tiles);
  writeDemAt(dem, 40, 40);
  for (const std::string& options : std::vector<std::string>{
           " --tile-size 16 --method rays", " --tile-size 16 --svf " + quoted(dir.path() / "s.tif"),
           " --tile-size 16 --max-distance 100 --near-reach 4000"}) {
    const auto r = runTool("aal-bake", quoted(dem) + " -q -o " + quoted(tiles) + options);
    EXPECT_EQ(r.exitCode, 2) << options << "\n" << r.out;
    EXPECT_TRUE(entriesOf(tiles).empty())
        << options << " left " << ::testing::PrintToString(entriesOf(tiles));
  }
  // Finished, then refused as a bake of another DEM (under the lock).
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -q --azimuths 4 --tile-size 16 -o " + quoted(tiles))
                .exitCode,
            0);
  EXPECT_FALSE(fs::exists(tiles / ".aal-bake.lock"));
  const FolderContents baked = test::folderContents(tiles);
  const fs::path otherDem = dir.path() / "e.tif";
  writeDemAt(otherDem, 40, 40, 30, 2);
  const auto other =
      runTool("aal-bake", quoted(otherDem) + " -q --azimuths 4 --tile-size 16 -o " + quoted(tiles));
  EXPECT_EQ(other.exitCode, 2) << other.out;
  EXPECT_NE(other.out.find("holds the tiled bake of another DEM"), std::string::npos) << other.out;
  EXPECT_TRUE(test::changedFiles(baked, test::folderContents(tiles)).empty())
      << ::testing::PrintToString(test::changedFiles(baked, test::folderContents(tiles)));
  // A killed bake's lock file goes with the next bake that takes the lock.
  std::ofstream(tiles / ".aal-bake.lock");
  const auto again =
      runTool("aal-bake", quoted(otherDem) + " -q --azimuths 4 --tile-size 16 -o " + quoted(tiles));
  EXPECT_EQ(again.exitCode, 2) << again.out;
  EXPECT_TRUE(test::changedFiles(baked, test::folderContents(tiles)).empty());
}

// aal-synth wrote a GeoTIFF named x.png, and ignored AAL_MEMORY_LIMIT.
TEST(HostileInput, AalSynthWritesGeoTiffsOnlyAndWithinTheMemoryLimit) {
  TempDir dir;
  for (const char* name : {"x.png", "x.asc", "x"}) {
    const auto r = runTool("aal-synth", "--size 8 -o " + quoted(dir.path() / name));
    EXPECT_EQ(r.exitCode, 2) << name << "\n" << r.out;
    EXPECT_NE(r.out.find("aal-synth writes a GeoTIFF; give a name ending in .tif or .tiff"),
              std::string::npos)
        << r.out;
  }
  const auto r =
      runTool("aal-synth", "--size 1024 -o " + quoted(dir.path() / "x.tif"), "AAL_MEMORY_LIMIT=1M");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("holding its 1024 x 1024 heights needs 4.2 MB, but only 1.0 MB of memory is "
                       "available (AAL_MEMORY_LIMIT); give a smaller --size, or a larger "
                       "AAL_MEMORY_LIMIT"),
            std::string::npos)
      << r.out;
  EXPECT_TRUE(entriesOf(dir.path()).empty());
  EXPECT_EQ(
      runTool("aal-synth", "--size 8 -o " + quoted(dir.path() / "x.TIFF"), "AAL_MEMORY_LIMIT=1M")
          .exitCode,
      0);
}

// Cameras are checked alike wherever they come from: a camera path's field
// of view as --fov's [1, 170] (1e-300 rendered flat grey with exit 0), and
// every point within cameraReachM of the DEM (1e300 m too), before the bake.
TEST(HostileInput, CamerasOutsideTheirRangesAreRefusedBeforeTheBake) {
  TempDir dir;
  const fs::path dem = dir.path() / "d.tif", cache = dir.path() / "cache";
  writeDemAt(dem, 32, 32);
  const auto path = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir.path() / name) << text;
    return quoted(dir.path() / name);
  };
  const std::string narrow = path("narrow.txt", "0 -900 -900 500 0 0 0 1e-300\n");
  const std::string wide = path("wide.txt", "0 -900 -900 500 0 0 0 40\n1 0 0 500 0 0 0 171\n");
  const std::string far = path("far.txt", "0 -900 -900 500 0 0 0\n# far\n2 1e300 0 500 0 0 0\n");
  const std::string away = path("away.txt", "0 -900 -900 500 0 0 -2e7\n");
  const std::string out = quoted(dem) + " --size 32x18 -q -o " + quoted(dir.path() / "x.png");
  const std::string beyond =
      "m from the DEM's centre, beyond the 1e+07 m a camera and the point it looks at may be "
      "from it";
  for (const ToolCase& c : std::vector<ToolCase>{
           {"aal-render", out + " --camera-path " + narrow + " --frames 2"},
           {"aal-render", out + " --camera-path " + wide + " --frames 2"},
           {"aal-render", out + " --camera-path " + far + " --frames 2"},
           {"aal-render", out + " --camera-path " + away + " --frames 2"},
           {"aal-render", out + " --camera 1e300,0,0"},
           {"aal-render", out + " --camera 0,0,2e7"},
           {"aal-render", out + " --look-at 0,-1e8,0"},
           {"aal-view", quoted(dem) + " --frames 1 --camera-path " + narrow},
           {"aal-view", quoted(dem) + " --frames 1 --camera-path " + far},
       }) {
    const auto r = runTool(c.tool, c.arguments, "AAL_CACHE_DIR=" + quoted(cache));
    EXPECT_EQ(r.exitCode, 2) << c.arguments << "\n" << r.out;
    const bool fov = c.arguments.find("narrow") != std::string::npos ||
                     c.arguments.find("wide") != std::string::npos;
    EXPECT_NE(r.out.find(fov ? "degrees is outside [1, 170] (the range of --fov)" : beyond),
              std::string::npos)
        << c.arguments << "\n"
        << r.out;
  }
  const auto line = runTool("aal-render", out + " --camera-path " + narrow + " --frames 2");
  EXPECT_NE(line.out.find("narrow.txt line 1: field of view 1e-300 degrees"), std::string::npos)
      << line.out;
  const auto farLine = runTool("aal-render", out + " --camera-path " + far + " --frames 2",
                               "AAL_CACHE_DIR=" + quoted(cache));
  EXPECT_NE(farLine.out.find("far.txt line 3: the camera lies 1e+300 m from the DEM's centre"),
            std::string::npos)
      << farLine.out;
  EXPECT_FALSE(fs::exists(cache)) << "refused only after baking";
  EXPECT_FALSE(fs::exists(dir.path() / "x.png"));
}

// The far field needs a near reach of at least 16 cells, where its blocks
// are one cell (docs/baking.md, "Far field"): a shorter one is refused
// with the minimum rather than baked with blocks too coarse for it.
TEST(HostileInput, ANearReachBelowTheFarFieldsMinimumIsRefused) {
  TempDir dir;
  const fs::path dem = dir.path() / "d.tif", tiles = dir.path() / "tiles";
  writeDemAt(dem, 40, 40);  // 30 m cells: at least 16 x 30 = 480 m
  for (const std::string reach : {"1", "450"}) {
    const auto r = runTool("aal-bake", quoted(dem) + " --tile-size 16 -q --near-reach " + reach +
                                           " -o " + quoted(tiles));
    EXPECT_EQ(r.exitCode, 2) << r.out;
    EXPECT_NE(r.out.find("--near-reach " + reach +
                         " m is shorter than the far field allows: at least 480 m (16 cells of "
                         "30 m, where the far field's blocks are one cell"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("give at least 480, or leave the option out (the default: 3840 m)"),
              std::string::npos)
        << r.out;
  }
  EXPECT_EQ(entriesOf(dir.path()), std::vector<std::string>{"d.tif"});
  EXPECT_EQ(runTool("aal-bake", quoted(dem) +
                                    " --tile-size 16 --azimuths 4 -q --near-reach 480 "
                                    "-o " +
                                    quoted(tiles))
                .exitCode,
            0);
}

// aal-render ignored --lat and --lon without --time; aal-relief refused
// them. Both refuse them alike now.
TEST(HostileInput, APlaceWithoutATimeIsRefusedByEveryTool) {
  TempDir dir;
  for (const ToolCase& c : std::vector<ToolCase>{
           {"aal-render",
            quoted(kDem) + " --size 32x18 -o " + quoted(dir.path() / "x.png") + " --lat 40"},
           {"aal-render", quoted(kDem) + " --size 32x18 -o " + quoted(dir.path() / "x.png") +
                              " --lon 10 --sun-azimuth 90 --sun-elevation 30"},
           {"aal-relief", quoted(kDem) + " -o " + quoted(dir.path() / "x.tif") + " --lat 40"},
       }) {
    const auto r = runTool(c.tool, c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.arguments << "\n" << r.out;
    EXPECT_NE(r.out.find("--lat and --lon place the sun for --time"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("give --time too"), std::string::npos) << r.out;
  }
  EXPECT_TRUE(entriesOf(dir.path()).empty());
}

// A 64 x 5 DEM of 0.3 m cells was refused for an --obscurance-radius no one
// had given ("at most the DEM's shorter side (1.200000 m), got 1.200000"),
// even with --no-obscurance: the default, the shorter side in single
// precision, lay above it in double. Only a radius typed is checked now.
TEST(HostileInput, ADerivedObscuranceRadiusIsNeverRefused) {
  TempDir dir;
  const fs::path dem = dir.path() / "narrow.tif";
  writeDemAt(dem, 64, 5, 0.3);
  const std::string cache = "AAL_CACHE_DIR=" + quoted(dir.path() / "cache");
  for (const ToolCase& c : std::vector<ToolCase>{
           {"aal-relief", quoted(dem) + " -q -o " + quoted(dir.path() / "r.tif")},
           {"aal-relief", quoted(dem) + " -q --no-obscurance -o " + quoted(dir.path() / "r.tif")},
           {"aal-render", quoted(dem) +
                              " --mode reference --reference-sun-rays 1 "
                              "--reference-sky-rays 1 --reference-subpixels 1 --size "
                              "16x9 -q -o " +
                              quoted(dir.path() / "r.png")},
           {"aal-render",
            quoted(dem) + " --size 16x9 -q --no-obscurance -o " + quoted(dir.path() / "r.png")},
       }) {
    const auto r = runTool(c.tool, c.arguments, cache);
    EXPECT_EQ(r.exitCode, 0) << c.arguments << "\n" << r.out;
  }
  const auto typed = runTool(
      "aal-relief", quoted(dem) + " -q --obscurance-radius 5 -o " + quoted(dir.path() / "t.tif"));
  EXPECT_EQ(typed.exitCode, 2) << typed.out;
  EXPECT_NE(typed.out.find("--obscurance-radius 5 m: the radius must be more than 0 and at most "
                           "the DEM's shorter side, 1.2 m; give one in that range, or leave the "
                           "option out"),
            std::string::npos)
      << typed.out;
  EXPECT_FALSE(fs::exists(dir.path() / "t.tif"));
}

// A bake that reads the DEM in windows (--low-memory) and still does not fit
// under AAL_MEMORY_LIMIT was told to use --low-memory.
TEST(HostileInput, ALowMemoryBakeBeyondTheLimitIsToldWhatHelps) {
  TempDir dir;
  const fs::path dem = dir.path() / "d.tif", tiles = dir.path() / "tiles";
  writeDemAt(dem, 256, 256);
  const auto r =
      runTool("aal-bake", quoted(dem) + " --tile-size 64 --low-memory -q -o " + quoted(tiles),
              "AAL_MEMORY_LIMIT=100K");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("of memory is available (AAL_MEMORY_LIMIT)"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("(--low-memory)"), std::string::npos) << r.out;
  // Refused before the checksum pass, with what the whole tiled bake holds.
  EXPECT_NE(r.out.find("holding a tiled bake read in windows (64-texel tiles"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("give a smaller --tile-size"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(tiles));
}

}  // namespace
}  // namespace aal

namespace aal {
namespace {

// A VRT over `source` whose placement (`placement`: a <GeoTransform> or
// <GCPList> element) and band (`band`: <Scale>, <Offset>) are as given.
void writeVrtPlaced(const fs::path& path, const std::string& source, const std::string& placement,
                    const std::string& band = "") {
  std::ofstream(path) << "<VRTDataset rasterXSize=\"64\" rasterYSize=\"64\">\n  " << placement
                      << "\n  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n    " << band
                      << "\n    <SimpleSource>\n      <SourceFilename relativeToVRT=\"1\">"
                      << source << "</SourceFilename>\n      <SourceBand>1</SourceBand>\n"
                      << "    </SimpleSource>\n  </VRTRasterBand>\n</VRTDataset>\n";
}

// Georeferencing and band metadata that cannot be used are named for what
// they are, with the command that fixes them: a zero pixel size (a GeoTIFF
// with a zero scale keeps only its tie point, which GDAL hands over as one
// ground control point), a band scale of 0 (taken as 1, with a warning) or
// NaN (refused).
TEST(HostileInput, GeoreferencingThatPlacesNoGridIsNamed) {
  TempDir dir;
  writeDemAt(dir.path() / "src.tif", 64, 64);
  struct Case {
    std::string name, placement, band;
    int exitCode;
    std::string says;
  };
  const std::vector<Case> cases = {
      {"tiepoint.vrt",
       "<GCPList><GCP Id=\"1\" Pixel=\"0\" Line=\"0\" X=\"500000\" Y=\"4000000\"/></GCPList>", "",
       2, "has a tie point but no pixel size (zero or missing in the file)"},
      {"zero.vrt", "<GeoTransform>500000, 0, 0, 4000000, 0, -30</GeoTransform>", "", 2,
       "has a pixel size of 0 x 30, which places no grid; give it one: `gdal_edit.py -a_ullr"},
      {"scale0.vrt", "<GeoTransform>500000, 30, 0, 4000000, 0, -30</GeoTransform>",
       "<Scale>0</Scale>", 0,
       "has a band scale of 0, which would flatten every height: taken as 1 (no scale)"},
      {"scalenan.vrt", "<GeoTransform>500000, 30, 0, 4000000, 0, -30</GeoTransform>",
       "<Scale>nan</Scale>", 2, "has a band scale of nan and offset of 0, which give no heights"},
  };
  for (const Case& c : cases) {
    writeVrtPlaced(dir.path() / c.name, "src.tif", c.placement, c.band);
    const auto r = runWithin10s("aal-info", quoted(dir.path() / c.name));
    EXPECT_EQ(r.exitCode, c.exitCode) << c.name << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.name << "\n" << r.out;
    EXPECT_EQ(r.out.find("ground control points"), std::string::npos) << c.name << "\n" << r.out;
  }
  // Scale 0 taken as 1: the heights are the source's.
  const auto plain = runWithin10s("aal-info", quoted(dir.path() / "src.tif"));
  const auto scaled = runWithin10s("aal-info", quoted(dir.path() / "scale0.vrt"));
  const auto heights = [](const std::string& text) {
    const size_t at = text.find("heights");
    return at == std::string::npos ? std::string() : text.substr(at, text.find('\n', at) - at);
  };
  EXPECT_FALSE(heights(plain.out).empty()) << plain.out;
  EXPECT_EQ(heights(plain.out), heights(scaled.out)) << scaled.out;
}

// A DEM whose name starts with '-' is read as an option by every command
// line; the error says so and how to give it, and `--` or ./ open it.
TEST(HostileInput, AFileNamedLikeAnOptionIsExplained) {
  TempDir dir;
  fs::copy_file(kDem, dir.path() / "-x.tif");
  for (const std::string tool : {"aal-info", "aal-bake", "aal-render", "aal-relief"}) {
    const std::string output = tool == "aal-info" ? "" : " -o out.tif";
    const auto r = runWithin10s(tool, "-x.tif" + output, dir.path());
    EXPECT_EQ(r.exitCode, 2) << tool << "\n" << r.out;
    EXPECT_NE(r.out.find("note: '-x.tif' is a file but was read as an option; give it as "
                         "./-x.tif or after --"),
              std::string::npos)
        << tool << "\n"
        << r.out;
  }
  EXPECT_EQ(runWithin10s("aal-info", "-- -x.tif", dir.path()).exitCode, 0);
  EXPECT_EQ(runWithin10s("aal-info", "./-x.tif", dir.path()).exitCode, 0);
  // An unknown option that is no file gets no note.
  const auto r = runWithin10s("aal-info", "--no-such-option " + quoted(kDem));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.out.find("note:"), std::string::npos) << r.out;
}

// A remote DEM that cannot be fetched (here: a closed port on this machine)
// is said to be unreachable, not "not a raster"; a missing archive is said
// to be missing.
TEST(HostileInput, AnUnreachableOrMissingVirtualFileIsSaidToBeSo) {
  TempDir dir;
  const auto r = runWithin10s("aal-info", "/vsicurl/http://127.0.0.1:9/dem.tif", {},
                              "GDAL_HTTP_TIMEOUT=5 GDAL_HTTP_MAX_RETRY=0");
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("/vsicurl/http://127.0.0.1:9/dem.tif: cannot be fetched: the server "
                       "cannot be reached or has no such file"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("unrecognised format"), std::string::npos) << r.out;
  writeDemAt(dir.path() / "dem.tif", 32, 32);
  ASSERT_EQ(test::runShell("cd " + quoted(dir.path()) + " && gzip -k dem.tif").exitCode, 0);
  const auto missing = runWithin10s("aal-info", "/vsigzip/other.tif.gz", dir.path());
  EXPECT_EQ(missing.exitCode, 2) << missing.out;
  EXPECT_NE(missing.out.find("/vsigzip/other.tif.gz: not found: the archive or the file in it "
                             "does not exist"),
            std::string::npos)
      << missing.out;
  EXPECT_EQ(runWithin10s("aal-info", "/vsigzip/dem.tif.gz", dir.path()).exitCode, 0);
}

// A DEM whose render or relief would not fit is refused before its samples
// are read, with what the whole run needs: an 8000² VRT (over a small
// source) reads in 320 MB, but a render holds 32 bytes per texel (2.05 GB)
// and a relief 28 (docs/performance.md, "Memory"). It used to pass the
// read's check and end in std::bad_alloc half-way.
TEST(HostileInput, ARunThatWouldNotFitIsRefusedBeforeItsDemIsRead) {
  TempDir dir;
  writeDemAt(dir.path() / "src.tif", 64, 64);
  writeVrt(dir.path() / "big.vrt", "src.tif", 8000, 8000);
  const std::string dem = quoted(dir.path() / "big.vrt"), out = quoted(dir.path() / "out");
  const std::vector<std::pair<ToolCase, std::string>> cases = {
      {{"aal-render", dem + " --size 32x18 -o " + out + ".png"},
       "holding a render of its 8000 x 8000 texels (32 bytes per texel) needs 2.05 GB"},
      {{"aal-relief", dem + " -o " + out + ".tif"},
       "holding a relief of its 8000 x 8000 texels (28 bytes per texel) needs 1.79 GB"},
      {{"aal-view", dem}, "holding the viewer's terrain of its 8000 x 8000 texels"},
  };
  for (const auto& [c, says] : cases) {
    const auto r = runWithin10s(c.tool, c.arguments, {}, "AAL_MEMORY_LIMIT=1G");
    EXPECT_EQ(r.exitCode, 2) << c.tool << "\n" << r.out;
    EXPECT_NE(r.out.find(says), std::string::npos) << c.tool << "\n" << r.out;
    EXPECT_NE(r.out.find("(AAL_MEMORY_LIMIT); cut the DEM"), std::string::npos) << r.out;
  }
  EXPECT_EQ(entriesOf(dir.path()), (std::vector<std::string>{"big.vrt", "src.tif"}));
}

// Every tool installs the interrupt handler (tools/tool_main.h): the first
// SIGINT, SIGTERM or SIGHUP stops it within a second at whatever it is
// doing, exit status non-zero, and leaves no temporary. aal-render and
// aal-info had none: a background run from a script (SIGINT ignored there)
// went on to the end, and a killed run could leave a temporary behind.
TEST(HostileInput, EveryToolStopsWithinASecondOfTheFirstSignal) {
  TempDir dir;
  writeDemAt(dir.path() / "src.tif", 64, 64);
  writeVrt(dir.path() / "big.vrt", "src.tif", 12000, 12000);
  const std::string vrt = (dir.path() / "big.vrt").string();
  const std::string out = (dir.path() / "out").string();
  const std::vector<std::vector<std::string>> runs = {
      {"aal-render", vrt, "--mode", "reference", "--size", "32x18", "-q", "-o", out + ".png"},
      {"aal-info", vrt},
      {"aal-relief", vrt, "-q", "-o", out + ".tif"},
      {"aal-synth", "--size", "8192", "-o", out + ".tif"},
  };
  for (const int signal : {SIGINT, SIGTERM, SIGHUP}) {
    for (const std::vector<std::string>& run : runs) {
      const std::string tool = (test::binDir() / run[0]).string();
      std::vector<char*> argv = {const_cast<char*>(tool.c_str())};
      for (size_t i = 1; i < run.size(); ++i) argv.push_back(const_cast<char*>(run[i].c_str()));
      argv.push_back(nullptr);
      // The three signals at their default actions, whatever this process's
      // are (a tool keeps a signal ignored when it starts ignored: below).
      posix_spawnattr_t attributes;
      posix_spawnattr_init(&attributes);
      sigset_t defaults;
      sigemptyset(&defaults);
      for (const int s : {SIGINT, SIGTERM, SIGHUP}) sigaddset(&defaults, s);
      posix_spawnattr_setsigdefault(&attributes, &defaults);
      posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF);
      pid_t pid = 0;
      ASSERT_EQ(posix_spawn(&pid, tool.c_str(), nullptr, &attributes, argv.data(), environ), 0);
      posix_spawnattr_destroy(&attributes);
      for (int i = 0; i < 200 && !test::catchesSignal(pid, signal); ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      EXPECT_TRUE(test::catchesSignal(pid, signal)) << run[0] << " " << signal;
      std::this_thread::sleep_for(std::chrono::milliseconds(400));  // at work by now
      const auto signalled = std::chrono::steady_clock::now();
      ::kill(pid, signal);
      int status = 0;
      ASSERT_EQ(::waitpid(pid, &status, 0), pid);
      const double seconds =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - signalled).count();
      EXPECT_LT(seconds, 1.0 + 0.5) << run[0] << " " << signal;  // a margin for a loaded machine
      EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << run[0] << " " << status;
      EXPECT_EQ(entriesOf(dir.path()), (std::vector<std::string>{"big.vrt", "src.tif"}))
          << run[0] << " " << signal;
    }
  }
}

// A signal ignored when the tool starts stays ignored: `nohup aal-bake ...`
// must outlive the terminal's SIGHUP. The tool still stops on SIGTERM.
TEST(HostileInput, ASignalIgnoredAtStartStaysIgnored) {
  TempDir dir;
  const std::string synth = (test::binDir() / "aal-synth").string();
  const std::string command =
      "trap '' HUP; exec " + synth + " --size 8192 -o " + quoted(dir.path() / "s.tif");
  const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ), 0);
  for (int i = 0; i < 200 && !test::catchesSignal(pid, SIGTERM); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(test::catchesSignal(pid, SIGTERM));
  EXPECT_FALSE(test::catchesSignal(pid, SIGHUP));
  ::kill(pid, SIGHUP);
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // past the watchdog's grace
  int status = 0;
  EXPECT_EQ(::waitpid(pid, &status, WNOHANG), 0) << "SIGHUP ended it";
  ::kill(pid, SIGTERM);
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << status;
  EXPECT_TRUE(entriesOf(dir.path()).empty());
}

}  // namespace
}  // namespace aal
