// Camera path files for scripted viewer runs (terrain/view/camera_path.h).
#include <gtest/gtest.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/view/camera_path.h"

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

}  // namespace
}  // namespace aal
