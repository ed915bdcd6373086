// gdaldem color-relief ramp files and the built-in palettes (terrain/reference/color_ramp.h).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/reference/color_ramp.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

ColorRamp parse(const std::string& text) {
  std::istringstream in(text);
  return parseColorRamp(in, "ramp.txt");
}

// The message of the InputError that parsing `text` throws.
std::string errorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ColorRamp, InterpolatesAtAndBetweenEntriesAndClampsBeyond) {
  // Out of order, mixed separators, a comment and a blank line, as gdaldem takes them.
  const ResolvedColorRamp r = resolveColorRamp(
      parse("# heights in metres\n1000 200 100 0\n\n0,0,0,100\n500:100:50:50:128\n"), 0, 0);
  ASSERT_EQ(r.heights.size(), 3u);
  EXPECT_EQ(r.heights[0], 0);
  EXPECT_EQ(r.heights[2], 1000);
  EXPECT_EQ(rampColor(r, 0), glm::vec4(0, 0, 100, 255));
  EXPECT_EQ(rampColor(r, 500), glm::vec4(100, 50, 50, 128));
  EXPECT_EQ(rampColor(r, 1000), glm::vec4(200, 100, 0, 255));
  EXPECT_EQ(rampColor(r, 250), glm::vec4(50, 25, 75, 191.5f));
  EXPECT_EQ(rampColor(r, 875), glm::vec4(175, 87.5f, 12.5f, 223.25f));
  EXPECT_EQ(rampColor(r, -40), glm::vec4(0, 0, 100, 255));
  EXPECT_EQ(rampColor(r, 1e6), glm::vec4(200, 100, 0, 255));
  EXPECT_FALSE(r.nodata);
}

TEST(ColorRamp, PercentagesSpanTheHeightRangeAndNvIsNodata) {
  const ColorRamp ramp = parse("0% 0 0 0\n50% 100 100 100\n100% 200 200 200\nnv 1 2 3 0\n");
  ASSERT_TRUE(ramp.nodata);
  EXPECT_EQ(*ramp.nodata, glm::vec4(1, 2, 3, 0));
  const ResolvedColorRamp r = resolveColorRamp(ramp, 200, 600);
  EXPECT_EQ(r.heights, (std::vector<double>{200, 400, 600}));
  EXPECT_EQ(rampColor(r, 300), glm::vec4(50, 50, 50, 255));
  EXPECT_EQ(rampColor(r, 500), glm::vec4(150, 150, 150, 255));
}

TEST(ColorRamp, BadLinesAreRefusedWithTheirLineNumber) {
  EXPECT_NE(errorOf("0 0 0 0\n10 1 2\n").find("ramp.txt:2:"), std::string::npos)
      << errorOf("0 0 0 0\n10 1 2\n");
  EXPECT_NE(errorOf("0 0 0 0\n\n10 1 2 300\n").find("ramp.txt:3: colour values"),
            std::string::npos);
  EXPECT_NE(errorOf("abc 1 2 3\n").find("ramp.txt:1: the elevation"), std::string::npos);
  EXPECT_NE(errorOf("150% 1 2 3\n").find("ramp.txt:1: a percentage"), std::string::npos);
  EXPECT_NE(errorOf("0 white\n").find("ramp.txt:1:"), std::string::npos);
  EXPECT_NE(errorOf("nan 1 2 3\n").find("ramp.txt:1:"), std::string::npos);
  EXPECT_NE(errorOf("# nothing\nnv 0 0 0\n").find("at least one"), std::string::npos);
  EXPECT_EQ(errorOf("0 1 2 3\n"), "no error");
}

// Ramp files are text inputs (terrain/io/input_file.h): a UTF-8 byte order
// mark at the start is skipped (editors on Windows write one); a folder, a
// device (/dev/zero read without end), a FIFO or a file over the 16 MiB cap
// (a sparse one: refused by its size, unread) is refused naming the file.
TEST(ColorRamp, RampFilesAreTextFilesOfAtMost16MiBAndMayStartWithAByteOrderMark) {
  test::TempDir dir;
  const std::filesystem::path bom = dir.path() / "bom.txt";
  std::ofstream(bom, std::ios::binary) << "\xEF\xBB\xBF"
                                       << "0 10 20 30\n100 40 50 60\n";
  const ColorRamp ramp = readColorRamp(bom.string());
  ASSERT_EQ(ramp.entries.size(), 2u);
  EXPECT_EQ(ramp.entries[0].value, 0);
  EXPECT_EQ(ramp.entries[0].rgba[0], 10);

  const std::filesystem::path big = dir.path() / "big.txt", fifo = dir.path() / "fifo.txt";
  std::ofstream(big).close();
  std::filesystem::resize_file(big, kMaxTextInputBytes + 1);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  ::alarm(10);  // a read that blocks ends the test
  const auto start = std::chrono::steady_clock::now();
  struct Case {
    std::string path, says;
  };
  for (const Case& c :
       {Case{"/dev/zero", "colour ramp /dev/zero is a character device, not a file"},
        Case{fifo.string(), "colour ramp " + fifo.string() + " is a FIFO, not a file"},
        Case{dir.path().string(),
             "colour ramp " + dir.path().string() + " is a folder, not a file"},
        Case{big.string(), "colour ramp " + big.string() +
                               " holds more than the 16 MiB (16777216 bytes) a colour ramp may "
                               "hold"}}) {
    try {
      readColorRamp(c.path);
      ADD_FAILURE() << c.path << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(c.says), std::string::npos) << e.what();
    }
  }
  ::alarm(0);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
}

TEST(ColorRamp, BuiltinPalettes) {
  for (const std::string& name : builtinPaletteNames()) {
    const ResolvedColorRamp r = resolveColorRamp(builtinPalette(name), 100, 300);
    EXPECT_EQ(r.heights.front(), 100) << name;
    EXPECT_EQ(r.heights.back(), 300) << name;
  }
  EXPECT_THROW(builtinPalette("rainbow"), InputError);
}

}  // namespace
}  // namespace aal
