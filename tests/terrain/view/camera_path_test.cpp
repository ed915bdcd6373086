// Camera path files for scripted viewer runs (terrain/view/camera_path.h).
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/view/camera_path.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

TEST(CameraPath, ParsesKeyframesCommentsAndBlankLines) {
  const CameraPath path = CameraPath::parse(
      "# a path\n"
      "0  -100 0 50   0 0 0\n"
      "\n"
      "2\t100 0 50    0 0 0  60  # wider\n",
      "test");
  ASSERT_EQ(path.keyframes().size(), 2u);
  EXPECT_EQ(path.startS(), 0);
  EXPECT_EQ(path.endS(), 2);
  EXPECT_EQ(path.keyframes()[0].camera.verticalFovDeg, 40);
  EXPECT_EQ(path.keyframes()[1].camera.verticalFovDeg, 60);
}

TEST(CameraPath, InterpolatesLinearlyAndClampsAtTheEnds) {
  const CameraPath path =
      CameraPath::parse("0 -100 0 50 0 0 0 40\n2 100 0 150 0 10 0 60\n", "test");
  const Camera mid = path.at(0.5);
  EXPECT_DOUBLE_EQ(mid.position.x, -50);
  EXPECT_DOUBLE_EQ(mid.position.z, 75);
  EXPECT_DOUBLE_EQ(mid.lookAt.y, 2.5);
  EXPECT_DOUBLE_EQ(mid.verticalFovDeg, 45);
  EXPECT_DOUBLE_EQ(path.at(-1).position.x, -100);
  EXPECT_DOUBLE_EQ(path.at(9).position.x, 100);
}

TEST(CameraPath, FramesSpreadFromFirstToLastKeyframe) {
  const CameraPath path = CameraPath::parse("1 0 0 50 1 0 50\n3 0 0 50 1 0 50\n", "test");
  EXPECT_DOUBLE_EQ(path.frameTime(0, 5), 1);
  EXPECT_DOUBLE_EQ(path.frameTime(2, 5), 2);
  EXPECT_DOUBLE_EQ(path.frameTime(4, 5), 3);
  EXPECT_DOUBLE_EQ(path.frameTime(0, 1), 1);
}

TEST(CameraPath, RejectsMalformedFilesNamingTheLine) {
  const char* bad[] = {
      "",                                // no keyframes
      "# only a comment\n",              // no keyframes
      "0 1 2 3 4 5\n",                   // too few numbers
      "0 1 2 3 4 5 6 7 8\n",             // too many
      "0 1 2 x 4 5 6\n",                 // not a number
      "0 1 2 3 4 5 6abc\n",              // trailing junk
      "0 nan 2 3 4 5 6\n",               // not finite
      "0 1 2 3 4 5 6\n0 1 2 3 4 5 7\n",  // time not increasing
      "0 1 2 3 1 2 3\n",                 // position equals look-at
      "0 1 2 3 4 5 6 180\n",             // field of view out of range
  };
  for (const char* text : bad) {
    EXPECT_THROW(CameraPath::parse(text, "p.txt"), InputError) << text;
  }
  try {
    CameraPath::parse("0 1 2 3 4 5 6\n\n1 1 2 3 4 5\n", "p.txt");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("p.txt line 3"), std::string::npos) << e.what();
  }
}

TEST(CameraPath, MissingFileIsAnInputError) {
  EXPECT_THROW(CameraPath::load("/nonexistent/path.txt"), InputError);
}

// Path files are text inputs (terrain/io/input_file.h): a UTF-8 byte order
// mark at the start is skipped; a folder, a FIFO, a device or a file over
// the 16 MiB cap is refused naming the file.
TEST(CameraPath, PathFilesAreTextFilesOfAtMost16MiBAndMayStartWithAByteOrderMark) {
  test::TempDir dir;
  const std::filesystem::path bom = dir.path() / "bom.txt";
  std::ofstream(bom, std::ios::binary) << "\xEF\xBB\xBF"
                                       << "0 -100 0 50 0 0 0\n2 100 0 50 0 0 0\n";
  EXPECT_EQ(CameraPath::load(bom.string()).keyframes().size(), 2u);

  const std::filesystem::path big = dir.path() / "big.txt", fifo = dir.path() / "fifo.txt";
  std::ofstream(big).close();
  std::filesystem::resize_file(big, (uint64_t{16} << 20) + 1);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  ::alarm(10);  // a read that blocks ends the test
  for (const auto& [path, says] : {
           std::pair{fifo.string(), " is a FIFO, not a file"},
           std::pair{std::string("/dev/zero"), " is a character device, not a file"},
           std::pair{dir.path().string(), " is a folder, not a file"},
           std::pair{big.string(), " holds more than the 16 MiB (16777216 bytes)"},
       }) {
    try {
      CameraPath::load(path);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("camera path " + path + says), std::string::npos)
          << e.what();
    }
  }
  ::alarm(0);
}

}  // namespace
}  // namespace aal
