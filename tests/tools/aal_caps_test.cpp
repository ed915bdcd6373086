// Command-line contract of aal-caps.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <regex>

#include "aperture/terrain/light/caps.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

using test::runTool;

double jsonNumber(const std::string& json, const std::string& key) {
  const std::regex pattern("\"" + key + "\": ([-+0-9.eE]+)");
  std::smatch match;
  if (!std::regex_search(json, match, pattern))
    throw std::runtime_error("no " + key + " in " + json);
  return std::stod(match[1]);
}

TEST(AalCaps, JsonGivesExactAndApproximateAreas) {
  const auto r = runTool("aal-caps", "0.5 0.7 0.9 --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NEAR(jsonNumber(r.out, "exact"), capIntersectionExact(0.5, 0.7, 0.9), 1e-7);
  EXPECT_NEAR(jsonNumber(r.out, "approx"), capIntersectionApprox(0.5f, 0.7f, 0.9f), 1e-6);
  const double abs = jsonNumber(r.out, "abs_error");
  EXPECT_NEAR(abs, std::abs(jsonNumber(r.out, "exact") - jsonNumber(r.out, "approx")), 1e-7);
  EXPECT_NEAR(jsonNumber(r.out, "rel_error"), abs / capArea(0.5), 1e-7);
}

TEST(AalCaps, DegreesAreConverted) {
  const auto r = runTool("aal-caps", "90 90 90 --degrees --json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NEAR(jsonNumber(r.out, "exact"), std::numbers::pi, 1e-7);  // a lune of 90 degrees
}

TEST(AalCaps, BadArgumentsExitWithTwo) {
  for (const char* args : {"", "1 2", "1 2 3 4", "-1 0.5 0.5", "nan 0.5 0.5", "4 0.5 0.5",
                           "abc 0.5 0.5", "200 10 10 --degrees", "--steps 1 --table x.csv",
                           "--max-radius 0 --table /tmp/aal-x.csv"}) {
    const auto r = runTool("aal-caps", args);
    EXPECT_EQ(r.exitCode, 2) << "args: '" << args << "'\n" << r.out;
    EXPECT_FALSE(r.out.empty()) << args;
  }
}

// One file for both outputs.
TEST(AalCaps, TableAndPlotInOneFileExitWithTwo) {
  test::TempDir dir;
  const std::string same = test::quoted(dir.path() / "x.png");
  const auto r = runTool("aal-caps", "--table " + same + " --plot " + same);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("is also the output of --table"), std::string::npos) << r.out;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "x.png"));
}

TEST(AalCaps, UnwritableOutputFailsBeforeWork) {
  const auto r = runTool("aal-caps", "--table /nonexistent-folder/t.csv");
  EXPECT_NE(r.exitCode, 0);
  EXPECT_NE(r.out.find("does not exist"), std::string::npos) << r.out;
}

TEST(AalCaps, TableAndPlotAreWritten) {
  test::TempDir dir;
  const auto table = dir.path() / "caps.csv";
  const auto plot = dir.path() / "caps.png";
  const auto r =
      runTool("aal-caps", "--steps 16 --table " + table.string() + " --plot " + plot.string());
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("radii <=  90.0 deg"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("radii <= 180.0 deg"), std::string::npos) << r.out;

  std::ifstream csv(table);
  std::string header, line;
  std::getline(csv, header);
  EXPECT_EQ(header, "r0_rad,r1_rad,d_rad,exact_sr,approx_sr,abs_error_sr,rel_error,partial");
  size_t rows = 0;
  while (std::getline(csv, line)) ++rows;
  EXPECT_EQ(rows, 16u * 16u * 33u);

  auto image = OIIO::ImageInput::open(plot.string());
  ASSERT_TRUE(image) << OIIO::geterror();
  EXPECT_GT(image->spec().width, 400);
  EXPECT_GT(image->spec().height, 400);
  // Only the final files remain: no temporaries left behind.
  size_t files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir.path()))
    ++files;
  EXPECT_EQ(files, 2u);
}

// OpenImageIO and its ~260 libraries come with the image plugin, loaded for
// the plot alone.
TEST(AalCaps, StartsWithoutOpenImageIo) {
  const auto ldd = test::runShell("ldd " + test::quoted(test::binDir() / "aal-caps"));
  ASSERT_EQ(ldd.exitCode, 0) << ldd.out;
  EXPECT_EQ(ldd.out.find("OpenImageIO"), std::string::npos) << ldd.out;
  const std::string missing = "/nonexistent/aal_oiio_images.so";
  const auto numbers = runTool("aal-caps", "0.5 0.7 0.9 --json", "AAL_IMAGE_PLUGIN=" + missing);
  EXPECT_EQ(numbers.exitCode, 0) << numbers.out;
  test::TempDir dir;
  const auto plot = runTool("aal-caps", "--plot " + test::quoted(dir.path() / "p.png"),
                            "AAL_IMAGE_PLUGIN=" + missing);
  EXPECT_EQ(plot.exitCode, 1) << plot.out;
  EXPECT_NE(plot.out.find("cannot load the image plugin " + missing), std::string::npos)
      << plot.out;
}

}  // namespace
}  // namespace aal
