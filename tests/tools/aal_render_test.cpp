// Command-line contract of aal-render (headless, lavapipe, validation on).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <filesystem>

#include "run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::runTool;
using test::TempDir;

using test::quoted;
const fs::path kDem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";

// Renders with a private bake cache so tests do not share state.
test::ToolResult render(const TempDir& dir, const std::string& args) {
  return runTool("aal-render", quoted(kDem) + " " + args,
                 "AAL_CACHE_DIR=" + quoted(dir.path() / "cache"));
}

OIIO::ImageSpec specOf(const fs::path& path) {
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return {};
  return in->spec();
}

TEST(AalRender, BakesCachesAndWritesAPng) {
  TempDir dir;
  const fs::path out = dir.path() / "a.png";
  auto r = render(dir, "-o " + quoted(out) + " --size 64x36 --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(specOf(out).width, 64);
  EXPECT_EQ(specOf(out).height, 36);
  EXPECT_NE(r.out.find("gpu terrain"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("triangles"), std::string::npos) << r.out;
  size_t cached = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path() / "cache")) ++cached;
  EXPECT_EQ(cached, 1u);
  // The second run uses the cache: same picture.
  const fs::path again = dir.path() / "b.png";
  ASSERT_EQ(render(dir, "-o " + quoted(again) + " --size 64x36").exitCode, 0);
  EXPECT_EQ(fs::file_size(out), fs::file_size(again));
}

TEST(AalRender, ExrIsLinearHdr) {
  TempDir dir;
  const fs::path out = dir.path() / "a.exr";
  ASSERT_EQ(render(dir, "-o " + quoted(out) + " --size 32x18 --time 2024-06-21T17:40:00Z").exitCode,
            0);
  const OIIO::ImageSpec spec = specOf(out);
  EXPECT_EQ(spec.width, 32);
  EXPECT_TRUE(spec.format.is_floating_point());
}

TEST(AalRender, NightAndACameraUnderTheGroundAreNotErrors) {
  TempDir dir;
  EXPECT_EQ(render(dir, "-o " + quoted(dir.path() / "n.png") +
                            " --size 32x18 --sun-azimuth 0 --sun-elevation -20")
                .exitCode,
            0);
  EXPECT_EQ(render(dir, "-o " + quoted(dir.path() / "u.png") +
                            " --size 32x18 --camera 0,0,-500 --look-at 1000,0,-500")
                .exitCode,
            0);
}

TEST(AalRender, BadInputExitsWithTwo) {
  TempDir dir;
  const std::string out = " -o " + quoted(dir.path() / "x.png");
  for (const std::string& args :
       {out + " --size 0x10", out + " --size 20000x10", out + " --size banana",
        " -o " + quoted(dir.path() / "x.jpg"), " -o " + quoted(dir.path() / "no" / "x.png"),
        out + " --time yesterday", out + " --sun-azimuth 10", out + " --mode magic",
        out + " --camera 1,2", out + " --albedo " + quoted(dir.path() / "missing.png"),
        out + " --aperture " + quoted(dir.path() / "missing.exr")}) {
    const auto r = render(dir, args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "x.png"));
}

TEST(AalRender, RefusesAnApertureMapOfAnotherDem) {
  TempDir dir;
  const fs::path other = dir.path() / "other.tif", map = dir.path() / "other.exr";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(other) + " --size 32").exitCode, 0);
  ASSERT_EQ(runTool("aal-bake", quoted(other) + " -o " + quoted(map) + " -q").exitCode, 0);
  const auto r = render(dir, "-o " + quoted(dir.path() / "x.png") + " --aperture " + quoted(map));
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("other.exr"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("jacksboro_fault_dem.tif"), std::string::npos) << r.out;
}

TEST(AalRender, NoVulkanDriverSaysHowToGetOne) {
  TempDir dir;
  const auto r =
      runTool("aal-render", quoted(kDem) + " -o " + quoted(dir.path() / "x.png"),
              "AAL_CACHE_DIR=" + quoted(dir.path() / "cache") +
                  " VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json");
  EXPECT_EQ(r.exitCode, 1) << r.out;
  EXPECT_NE(r.out.find("mesa-vulkan-drivers"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace aal
