// Command-line contract of aal-render (headless, lavapipe, validation on).
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "aperture/tests/tools/run_tool.h"

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

// The decoded 8-bit pixels of an image as stored (colour not multiplied by
// alpha), empty when it cannot be read.
std::vector<uint8_t> pixelsOf(const fs::path& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) return {};
  const OIIO::ImageSpec& spec = in->spec();
  std::vector<uint8_t> pixels(spec.image_pixels() * spec.nchannels);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::UINT8, pixels.data())) return {};
  return pixels;
}

// --pass-profile: each pass's wall-clock and CPU time, measured with the
// pass submitted on its own, against the frame in one submission; only for
// the GPU renderer's still image.
TEST(AalRender, PassProfileTimesEachPassAlone) {
  TempDir dir;
  const fs::path out = dir.path() / "a.png";
  const auto r = render(dir, "-o " + quoted(out) + " --size 64x36 --pass-profile 2");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  for (const char* line : {"pass profile: medians of 2 frames", "prepare (host)", "sky table",
                           "terrain + sky (G-buffer)", "obscurance filter", "composite",
                           "sum of the steps", "frame in one submission"}) {
    EXPECT_NE(r.out.find(line), std::string::npos) << line << "\n" << r.out;
  }
  const auto compare = render(dir, "--compare " + quoted(dir.path() / "cmp") + " --pass-profile 1");
  EXPECT_EQ(compare.exitCode, 2) << compare.out;
  EXPECT_NE(compare.out.find("--pass-profile"), std::string::npos) << compare.out;
  const auto zero = render(dir, "-o " + quoted(out) + " --pass-profile 0");
  EXPECT_EQ(zero.exitCode, 2) << zero.out;
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
  std::vector<fs::path> cached;
  for (const auto& e : fs::directory_iterator(dir.path() / "cache")) cached.push_back(e.path());
  ASSERT_EQ(cached.size(), 1u);
  const fs::file_time_type baked = fs::last_write_time(cached[0]);
  // The second run reads the cache (a rebake would rewrite the entry) and
  // draws the same picture.
  const fs::path again = dir.path() / "b.png";
  ASSERT_EQ(render(dir, "-o " + quoted(again) + " --size 64x36").exitCode, 0);
  EXPECT_TRUE(fs::last_write_time(cached[0]) == baked) << "the second run rewrote the cache entry";
  const std::vector<uint8_t> first = pixelsOf(out), second = pixelsOf(again);
  ASSERT_EQ(first.size(), 64u * 36 * 4);
  EXPECT_TRUE(first == second) << "the cached map's picture differs";
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
        out + " --camera 1,2", out + " --anisotropy 0", out + " --anisotropy 5",
        out + " --supersample 0", out + " --supersample 5", out + " --size 9000x8 --supersample 2",
        out + " --albedo " + quoted(dir.path() / "missing.png"),
        out + " --aperture " + quoted(dir.path() / "missing.exr")}) {
    const auto r = render(dir, args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "x.png"));
}

// NaN passes a plain range check: it must exit 2 and say which, not give an
// EXR full of NaN or, cast to an index, crash the reference renderer.
TEST(AalRender, NonFiniteNumbersExitWithTwoAndSayWhich) {
  TempDir dir;
  const std::string out = " -o " + quoted(dir.path() / "x.exr") + " --size 64x36";
  for (const std::string& args :
       {out + " --mode reference --fov nan", out + " --sun-elevation nan --sun-azimuth 10",
        out + " --sun-azimuth NaN --sun-elevation 20", out + " --ev inf",
        out + " --lat nan --lon 10", out + " --sun-radius nan",
        out + " --camera 1e999,0,0 --look-at 0,0,0", out + " --fov=nan"}) {
    const auto r = render(dir, args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("every number must be finite"), std::string::npos) << args << r.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "x.exr"));
}

// `aal-render DEM --aperture a.exr -o a.exr` must not overwrite the map it
// reads.
TEST(AalRender, AnOutputThatIsAnInputExitsWithTwo) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr", albedo = dir.path() / "albedo.png";
  std::ofstream(map, std::ios::binary) << "not really a map";
  std::ofstream(albedo, std::ios::binary) << "not really an image";
  for (const std::string& args : {"--aperture " + quoted(map) + " -o " + quoted(map),
                                  "--albedo " + quoted(albedo) + " -o " + quoted(albedo)}) {
    const auto r = render(dir, args + " --size 32x18");
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("writing it would destroy it"), std::string::npos) << r.out;
  }
  EXPECT_EQ(fs::file_size(map), 16u);
}

// A camera far beyond the DEM, within the reach the tools take (10,000 km
// here), does not crash the reference; 1e300 m away is refused before any
// work (it rendered nothing, with exit 0).
TEST(AalRender, ACameraFarBeyondTheDemDoesNotCrashTheReference) {
  TempDir dir;
  const auto r = render(dir, "-o " + quoted(dir.path() / "far.exr") +
                                 " --size 32x18 --mode reference --camera 9.9e6,0,0");
  EXPECT_EQ(r.exitCode, 0) << r.out;
  const auto absurd = render(dir, "-o " + quoted(dir.path() / "absurd.exr") +
                                      " --size 32x18 --mode reference --camera 1e300,0,0");
  EXPECT_EQ(absurd.exitCode, 2) << absurd.out;
  EXPECT_NE(absurd.out.find("--camera 1e300,0,0 lies 1e+300 m from the DEM's centre"),
            std::string::npos)
      << absurd.out;
  EXPECT_FALSE(fs::exists(dir.path() / "absurd.exr"));
}

TEST(AalRender, BadObscuranceOptionsExitWithTwoAndSayWhy) {
  TempDir dir;
  const std::string out = " -o " + quoted(dir.path() / "x.png") + " --size 32x18";
  const std::pair<std::string, std::string> cases[] = {
      {" --obscurance-samples 12", "--obscurance-samples"},
      {" --obscurance-steps 3", "--obscurance-steps"},
      {" --obscurance-radius 0", "--obscurance-radius"},
      {" --obscurance-radius -30", "--obscurance-radius"},
      {" --obscurance-radius 1e9", "shorter side"},
      {" --albedo-value 1.5", "--albedo-value"},
      {" --albedo-value banana", "--albedo-value"},
      {" --albedo-value 0.1,0.2", "--albedo-value"},
      {" --albedo-value 0.5 --albedo " + quoted(dir.path() / "a.png"), "not both"}};
  for (const auto& [args, message] : cases) {
    const auto r = render(dir, out + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "x.png"));
}

// The mean and minimum of the first channel over pixels whose value is > 0
// (debug views paint the sky black).
std::pair<double, float> terrainMeanAndMin(const fs::path& exr) {
  auto in = OIIO::ImageInput::open(exr.string());
  if (!in) return {-1, -1};
  const OIIO::ImageSpec spec = in->spec();
  std::vector<float> pixels(static_cast<size_t>(spec.width) * spec.height * spec.nchannels);
  in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, pixels.data());
  double sum = 0;
  float least = 2;
  int count = 0;
  for (size_t i = 0; i < pixels.size(); i += static_cast<size_t>(spec.nchannels)) {
    if (pixels[i] <= 0) continue;
    sum += pixels[i];
    least = std::min(least, pixels[i]);
    ++count;
  }
  return {count ? sum / count : -1, least};
}

TEST(AalRender, ObscuranceAndTransferViewsAreLinearInExr) {
  TempDir dir;
  const fs::path o = dir.path() / "o.exr", w = dir.path() / "w.exr", off = dir.path() / "off.exr";
  auto r = render(dir, "-o " + quoted(o) +
                           " --size 64x36 --mode debug-obscurance --obscurance-samples 8 "
                           "--obscurance-steps 2 --obscurance-radius 1500 --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("obscurance R 1500.0 m, n 8, m 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gpu obscurance"), std::string::npos) << r.out;
  ASSERT_EQ(render(dir, "-o " + quoted(w) +
                            " --size 64x36 --mode debug-transfer --obscurance-samples 8 "
                            "--obscurance-steps 2 --obscurance-radius 1500 --albedo-value 0.6")
                .exitCode,
            0);
  ASSERT_EQ(render(dir, "-o " + quoted(off) + " --size 64x36 --mode debug-transfer --no-obscurance")
                .exitCode,
            0);
  const auto [meanO, minO] = terrainMeanAndMin(o);
  const auto [meanW, minW] = terrainMeanAndMin(w);
  const auto [meanOff, minOff] = terrainMeanAndMin(off);
  // Linear values in (0, 1]: the valleys of jacksboro are obscured, W lifts
  // them with the bounced light, and without the pass W is 1.
  EXPECT_GT(minO, 0.0f);
  EXPECT_LT(minO, 0.95f);
  EXPECT_LT(meanO, 1.0);
  EXPECT_GT(meanW, meanO);
  EXPECT_LE(meanW, 1.0);
  EXPECT_EQ(minOff, 1.0f);
  EXPECT_EQ(meanOff, 1.0);
}

// --max-tile splits the DEM's textures into tiles (docs/rendering.md): the
// picture stays the single image's within 1 LSB (tests/engine/tile_render_test.cpp
// checks every mode).
TEST(AalRender, MaxTileTilesTheTexturesWithoutChangingThePicture) {
  TempDir dir;
  const fs::path single = dir.path() / "single.png", tiled = dir.path() / "tiled.png";
  const auto a = render(dir, "-o " + quoted(single) + " --size 160x90 --stats");
  ASSERT_EQ(a.exitCode, 0) << a.out;
  EXPECT_NE(a.out.find("in 1x1 tiles"), std::string::npos) << a.out;
  const auto b = render(dir, "-o " + quoted(tiled) + " --size 160x90 --stats --max-tile 100");
  ASSERT_EQ(b.exitCode, 0) << b.out;
  EXPECT_NE(b.out.find("403x344 texels in 5x4 tiles of 96x96"), std::string::npos) << b.out;
  const std::vector<uint8_t> x = pixelsOf(single), y = pixelsOf(tiled);
  ASSERT_EQ(x.size(), y.size());
  ASSERT_FALSE(x.empty());
  int worst = 0;
  for (size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(int(x[i]) - int(y[i])));
  EXPECT_LE(worst, 1);
  EXPECT_EQ(render(dir, "-o " + quoted(tiled) + " --max-tile 0").exitCode, 2);
  // Tiles below one texel of the coarsest mip level (32 DEM texels).
  const auto tooSmall = render(dir, "-o " + quoted(tiled) + " --max-tile 31");
  EXPECT_EQ(tooSmall.exitCode, 2) << tooSmall.out;
  EXPECT_NE(tooSmall.out.find("--max-tile"), std::string::npos) << tooSmall.out;
}

// The horizon mode with --max-tile: the directional horizons
// split in the textures' tiles give the single image's picture within
// 1 LSB, for 8-bit codes of 8 directions and 4-bit codes of 16, under a
// sun low enough for them to change the picture.
TEST(AalRender, MaxTileKeepsTheHorizonModesPicture) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr";
  const std::string sun = " --size 160x90 --sun-azimuth 250 --sun-elevation 12 --stats";
  for (const auto& [name, bake] : std::vector<std::pair<std::string, std::string>>{
           {"eight.horizons", " --horizon-directions 8 --horizon-bits 8"},
           {"four.horizons", " --horizon-directions 16 --horizon-bits 4"}}) {
    const fs::path horizons = dir.path() / name;
    ASSERT_EQ(runTool("aal-bake", quoted(kDem) + " -o " + quoted(map) + bake + " --horizons " +
                                      quoted(horizons) + " -q")
                  .exitCode,
              0);
    const std::string common =
        "--aperture " + quoted(map) + " --horizons " + quoted(horizons) + " --mode horizon" + sun;
    const fs::path single = dir.path() / "single.png", tiled = dir.path() / "tiled.png",
                   approx = dir.path() / "approx.png";
    ASSERT_EQ(render(dir, "-o " + quoted(approx) + " --aperture " + quoted(map) + sun).exitCode, 0);
    const auto a = render(dir, "-o " + quoted(single) + " " + common);
    ASSERT_EQ(a.exitCode, 0) << a.out;
    const auto b = render(dir, "-o " + quoted(tiled) + " " + common + " --max-tile 100");
    ASSERT_EQ(b.exitCode, 0) << b.out;
    EXPECT_NE(b.out.find("403x344 texels in 5x4 tiles of 96x96"), std::string::npos) << b.out;
    EXPECT_NE(b.out.find("horizons   "), std::string::npos) << b.out;
    std::printf("%s\n%s", name.c_str(), b.out.c_str());
    const std::vector<uint8_t> x = pixelsOf(single), y = pixelsOf(tiled), z = pixelsOf(approx);
    ASSERT_EQ(x.size(), y.size());
    ASSERT_EQ(x.size(), z.size());
    ASSERT_FALSE(x.empty());
    int worst = 0;
    size_t differs = 0;  // green channels more than 2 LSB from approx's
    for (size_t i = 0; i < x.size(); ++i) {
      worst = std::max(worst, std::abs(int(x[i]) - int(y[i])));
      if (i % 4 == 1 && std::abs(int(x[i]) - int(z[i])) > 2) ++differs;
    }
    EXPECT_LE(worst, 1) << name;
    std::printf("%s: %zu of %zu pixels more than 2 LSB from approx's\n", name.c_str(), differs,
                x.size() / 4);
    // Jacksboro's gentle relief: the horizons change under 1 % of the
    // picture at 12 degrees (1.4 % with the lower two of each 2 x 2 in the
    // levels and approx's sun edge a step at the footprint's mean; figures
    // now in the output above; at 6 the sun is hidden in both modes nearly
    // everywhere). Horizons ignored would change none.
    EXPECT_GT(differs, x.size() / 4 / 400) << name << ": the horizons change nothing";
  }
}

TEST(AalRender, AlbedoImageOfAnotherSizeIsResampledWithANote) {
  TempDir dir;
  const fs::path albedo = dir.path() / "albedo.png";
  {
    std::vector<uint8_t> grey(40 * 30 * 3, 128);
    auto image = OIIO::ImageOutput::create(albedo.string());
    ASSERT_TRUE(image);
    ASSERT_TRUE(image->open(albedo.string(), OIIO::ImageSpec(40, 30, 3, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(image->write_image(OIIO::TypeDesc::UINT8, grey.data()));
    image->close();
  }
  const auto r = render(
      dir, "-o " + quoted(dir.path() / "a.png") + " --size 32x18 --albedo " + quoted(albedo));
  EXPECT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("resampled to the DEM"), std::string::npos) << r.out;
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

// Directional horizons carry the heights' checksum (format version 3): of
// the same size but baked from other heights (here the DEM at twice its z
// scale), they are refused before anything is drawn; a file from before the
// checksum (version 2) is checked by its size alone, with a note. Since
// version 4 they carry the checksum of their codes too: other codes under
// the file's own header are refused.
TEST(AalRender, RefusesHorizonsBakedFromOtherHeights) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr", horizons = dir.path() / "a.horizons",
                 steep = dir.path() / "steep.horizons";
  ASSERT_EQ(test::bakeWithHorizons(kDem, map, horizons), 0);
  ASSERT_EQ(
      runTool("aal-bake", quoted(kDem) + " --z-scale 2 -o " + quoted(dir.path() / "steep.exr") +
                              " --horizons " + quoted(steep) + " -q")
          .exitCode,
      0);
  const std::string common = "-o " + quoted(dir.path() / "x.png") + " --size 32x18 --aperture " +
                             quoted(map) + " --mode horizon --horizons ";
  const auto ok = render(dir, common + quoted(horizons));
  EXPECT_EQ(ok.exitCode, 0) << ok.out;
  EXPECT_EQ(ok.out.find("predates"), std::string::npos) << ok.out;
  const auto other = render(dir, common + quoted(steep));
  EXPECT_EQ(other.exitCode, 2) << other.out;
  EXPECT_NE(other.out.find("steep.horizons was baked from other heights"), std::string::npos)
      << other.out;
  // The same codes under a version 2 header.
  std::ifstream in(horizons, std::ios::binary);
  std::string header;
  std::getline(in, header);
  const std::string codes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_EQ(header.rfind("aperture-horizons 4 403 344 8 8 r2-", 0), 0u) << header;
  const fs::path old = dir.path() / "old.horizons";
  std::ofstream(old, std::ios::binary) << "aperture-horizons 2 403 344 8 8\n" << codes;
  const auto legacy = render(dir, common + quoted(old));
  EXPECT_EQ(legacy.exitCode, 0) << legacy.out;
  EXPECT_NE(legacy.out.find("predates the heights checksum"), std::string::npos) << legacy.out;
  // A valid header over other codes (one byte flipped): refused, not drawn.
  std::string flipped = codes;
  flipped[flipped.size() / 2] ^= 0x10;
  const fs::path damaged = dir.path() / "damaged.horizons";
  std::ofstream(damaged, std::ios::binary) << header << "\n" << flipped;
  const auto refused = render(dir, common + quoted(damaged));
  EXPECT_EQ(refused.exitCode, 2) << refused.out;
  EXPECT_NE(refused.out.find("damaged.horizons is corrupt: its codes do not match the checksum"),
            std::string::npos)
      << refused.out;
  EXPECT_NE(refused.out.find("bake it again"), std::string::npos) << refused.out;
}

TEST(AalRender, RefusesAnApertureMapBakedForAnotherCellSize) {
  TempDir dir;
  const fs::path dem = dir.path() / "d.tif", map = dir.path() / "d.exr";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(dem) + " --size 32").exitCode, 0);
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " --cell-size 10 -o " + quoted(map) + " -q").exitCode,
            0);
  const std::string png = " -o " + quoted(dir.path() / "x.png") + " --size 32x18";
  const auto r =
      runTool("aal-render", quoted(dem) + " --cell-size 20 --aperture " + quoted(map) + png);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("baked for cells of 10 x 10 m, the DEM has 20 x 20 m"), std::string::npos)
      << r.out;
  EXPECT_EQ(runTool("aal-render", quoted(dem) + " --cell-size 10 --aperture " + quoted(map) + png)
                .exitCode,
            0);
  // The bake cache keeps one entry per cell size, not one for both.
  const std::string cache = "AAL_CACHE_DIR=" + quoted(dir.path() / "cache");
  for (const char* cell : {"10", "20", "10"}) {
    const auto run = runTool("aal-render", quoted(dem) + " --cell-size " + cell + png, cache);
    ASSERT_EQ(run.exitCode, 0) << run.out;
    EXPECT_EQ(run.out.find("rebaking"), std::string::npos) << run.out;
  }
  size_t cached = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path() / "cache")) ++cached;
  EXPECT_EQ(cached, 2u);
}

// --exaggeration X multiplies the heights; the aperture map is
// baked for it (one cache entry per exaggeration, reused), and a map baked
// for other heights is refused with the z scales and the way out named.
TEST(AalRender, ExaggerationBakesForItOrRefusesAMapOfAnotherZScale) {
  TempDir dir;
  const fs::path dem = dir.path() / "d.tif", map = dir.path() / "d.exr",
                 map3 = dir.path() / "d3.exr";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(dem) + " --size 48").exitCode, 0);
  const std::string cache = "AAL_CACHE_DIR=" + quoted(dir.path() / "cache");
  const auto shot = [&](const std::string& name, const std::string& extra) {
    const fs::path out = dir.path() / name;
    const auto r =
        runTool("aal-render", quoted(dem) + " -o " + quoted(out) + " --size 48x27 " + extra, cache);
    EXPECT_EQ(r.exitCode, 0) << r.out;
    EXPECT_EQ(r.out.find("rebaking"), std::string::npos) << r.out;
    return pixelsOf(out);
  };
  const std::vector<uint8_t> flat = shot("1.png", ""), tall = shot("3.png", "--exaggeration 3");
  ASSERT_FALSE(flat.empty());
  EXPECT_NE(flat, tall);
  EXPECT_EQ(shot("3b.png", "--exaggeration 3"), tall);  // from the cache, same picture
  size_t cached = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir.path() / "cache")) ++cached;
  EXPECT_EQ(cached, 2u);
  // A map baked without the exaggeration: refused, saying why and how.
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " -q").exitCode, 0);
  const std::string png = " -o " + quoted(dir.path() / "x.png") + " --size 48x27";
  const auto r = runTool("aal-render",
                         quoted(dem) + " --exaggeration 3 --aperture " + quoted(map) + png, cache);
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find("baked for heights at z scale 1, these are at 3"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("aal-bake --z-scale 3"), std::string::npos) << r.out;
  // The way out works: a map baked at that z scale draws the cached map's picture.
  ASSERT_EQ(runTool("aal-bake", quoted(dem) + " --z-scale 3 -o " + quoted(map3) + " -q").exitCode,
            0);
  EXPECT_EQ(shot("3c.png", "--exaggeration 3 --aperture " + quoted(map3)), tall);
  for (const char* bad : {"0", "-1", "101", "nan"}) {
    const auto e = runTool("aal-render", quoted(dem) + png + " --exaggeration " + bad, cache);
    EXPECT_EQ(e.exitCode, 2) << bad << "\n" << e.out;
    EXPECT_NE(e.out.find("--exaggeration"), std::string::npos) << e.out;
  }
}

// --base DEPTH draws walls and a bottom under the DEM: from a
// fixed camera more opaque pixels than without (transparent background), a
// deeper base more still; the default camera frames the base too (the last
// rows, the 5 % margin, stay empty); bad values exit 2.
TEST(AalRender, BaseAddsWallsUnderTheDem) {
  TempDir dir;
  const auto image = [&](const std::string& extra) {
    const fs::path out = dir.path() / "b.png";
    const auto r =
        render(dir, "-o " + quoted(out) + " --size 64x36 -q --background transparent " + extra);
    EXPECT_EQ(r.exitCode, 0) << r.out;
    return pixelsOf(out);
  };
  const auto opaque = [](const std::vector<uint8_t>& p) {
    size_t n = 0;
    for (size_t i = 3; i < p.size(); i += 4) n += p[i] > 0;
    return n;
  };
  const std::string camera = "--camera 30000,-30000,15000 --look-at 0,0,0 ";
  const size_t none = opaque(image(camera)), shallow = opaque(image(camera + "--base 500")),
               deep = opaque(image(camera + "--base 3000 --base-color 0.2,0.2,0.25"));
  EXPECT_GT(shallow, none + 32);
  EXPECT_GT(deep, shallow + 32);
  const std::vector<uint8_t> framed = image("--base 3000");
  ASSERT_EQ(framed.size(), 64u * 36 * 4);
  size_t lastRow = 0;
  for (size_t i = 3; i < framed.size(); i += 4) {
    if (framed[i] > 0) lastRow = (i / 4) / 64;
  }
  EXPECT_GE(lastRow, 30u);  // the base reaches the framed picture's lower margin
  EXPECT_LT(lastRow, 35u);  // and ends inside it
  for (const std::string& bad :
       {std::string("--base 0"), std::string("--base -5"), std::string("--base 100 --base-color 2"),
        std::string("--base 100 --base-color 0.1,0.2"),
        std::string("--base 100 --mode reference")}) {
    const auto e = render(dir, "-o " + quoted(dir.path() / "x.png") + " --size 32x18 " + bad);
    EXPECT_EQ(e.exitCode, 2) << bad << "\n" << e.out;
    EXPECT_NE(e.out.find("--base"), std::string::npos) << e.out;
  }
}

// --time-range START END --frames N writes OUT-0001.png
// ... OUT-000N.png, the first and last being the renders at START and END,
// with a progress bar (in runs over a second); without ffmpeg (AAL_FFMPEG set empty) no MP4 and a
// note saying how to get one.
TEST(AalRender, TimeRangeWritesANumberedSequence) {
  TempDir dir;
  const fs::path out = dir.path() / "day.png";
  const auto r = runTool("aal-render",
                         quoted(kDem) + " -o " + quoted(out) +
                             " --size 48x27 --time-range 2024-06-21T12:00Z 2024-06-22T00:00Z "
                             "--frames 3",
                         "AAL_FFMPEG= AAL_CACHE_DIR=" + quoted(dir.path() / "cache"));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  // The progress bar stays quiet in runs under a second (ProgressBar): the
  // summary line is what every run prints.
  EXPECT_NE(r.out.find("3 frames in"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("ffmpeg not found"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "day.mp4"));
  EXPECT_FALSE(fs::exists(out));
  const std::vector<uint8_t> first = pixelsOf(dir.path() / "day-0001.png"),
                             middle = pixelsOf(dir.path() / "day-0002.png"),
                             last = pixelsOf(dir.path() / "day-0003.png");
  ASSERT_EQ(first.size(), 48u * 27 * 4);
  EXPECT_FALSE(fs::exists(dir.path() / "day-0004.png"));
  const auto single = [&](const std::string& time) {
    const fs::path one = dir.path() / "one.png";
    EXPECT_EQ(render(dir, "-o " + quoted(one) + " --size 48x27 -q --time " + time).exitCode, 0);
    return pixelsOf(one);
  };
  EXPECT_EQ(first, single("2024-06-21T12:00:00Z"));
  EXPECT_EQ(middle, single("2024-06-21T18:00:00Z"));
  EXPECT_EQ(last, single("2024-06-22T00:00:00Z"));
  EXPECT_NE(first, middle);
}

// A --time-range sequence in the horizon mode: the horizons are laid out for
// the first frame's sun (Jacksboro, 2024-06-21 12:00 UTC: azimuth 73.6
// degrees, one layer of rotation 0 holds the directions beside it) and
// re-laid when a later sun needs it (00:00 UTC: 292.0 degrees, between
// stored directions 3 and 4 of 8, rotation 2); each frame equals the single
// render at its time, which lays them out for its own sun. Under validation,
// without a message.
TEST(AalRender, HorizonSequenceReLaysTheHorizonsForTheMovingSun) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr", horizons = dir.path() / "a.horizons";
  ASSERT_EQ(test::bakeWithHorizons(kDem, map, horizons), 0);
  const std::string common = "--aperture " + quoted(map) + " --horizons " + quoted(horizons) +
                             " --mode horizon --size 64x36 --no-obscurance -q ";
  const auto run = [&](const std::string& args) {
    return runTool("aal-render", quoted(kDem) + " " + common + args,
                   "AAL_VALIDATION=1 AAL_FFMPEG= AAL_CACHE_DIR=" + quoted(dir.path() / "cache"));
  };
  const fs::path out = dir.path() / "day.png";
  const auto r = run("-o " + quoted(out) + " --time-range 2024-06-21T12:00Z 2024-06-22T00:00Z " +
                     "--frames 3");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.out.find("validation"), std::string::npos) << r.out;
  for (const auto& [frame, time] :
       {std::pair{1, "2024-06-21T12:00:00Z"}, std::pair{2, "2024-06-21T18:00:00Z"},
        std::pair{3, "2024-06-22T00:00:00Z"}}) {
    const fs::path one = dir.path() / "one.png";
    const auto single = run("-o " + quoted(one) + " --time " + time);
    ASSERT_EQ(single.exitCode, 0) << single.out;
    EXPECT_EQ(single.out.find("validation"), std::string::npos) << single.out;
    const std::vector<uint8_t> pixels =
        pixelsOf(dir.path() / ("day-000" + std::to_string(frame) + ".png"));
    ASSERT_EQ(pixels.size(), 64u * 36 * 4);
    EXPECT_EQ(pixels, pixelsOf(one)) << "frame " << frame << " at " << time;
  }
}

// A --camera-path sequence (aal-view's format) frames its keyframes: with
// two keyframes and --frames 2 the images are the renders from each
// keyframe's --camera, --look-at and --fov (each frame on its own:
// --temporal off).
TEST(AalRender, CameraPathSequenceFollowsTheKeyframes) {
  TempDir dir;
  const fs::path path = dir.path() / "flight.txt", out = dir.path() / "fly.png";
  std::ofstream(path) << "# t x y z lx ly lz fov\n"
                         "0 -20000 -20000 6000 0 0 300 40\n"
                         "10 20000 -15000 4000 0 2000 300 55\n";
  const auto r =
      render(dir, "-o " + quoted(out) + " --size 48x27 -q --camera-path " + quoted(path) +
                      " --frames 2 --temporal off --sun-azimuth 200 --sun-elevation 40");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const auto single = [&](const std::string& camera) {
    const fs::path one = dir.path() / "one.png";
    EXPECT_EQ(render(dir, "-o " + quoted(one) +
                              " --size 48x27 -q --sun-azimuth 200 --sun-elevation 40 " + camera)
                  .exitCode,
              0);
    return pixelsOf(one);
  };
  const std::vector<uint8_t> a = pixelsOf(dir.path() / "fly-0001.png"),
                             b = pixelsOf(dir.path() / "fly-0002.png");
  ASSERT_FALSE(a.empty());
  EXPECT_EQ(a, single("--camera -20000,-20000,6000 --look-at 0,0,300 --fov 40"));
  EXPECT_EQ(b, single("--camera 20000,-15000,4000 --look-at 0,2000,300 --fov 55"));
}

// By default a --camera-path sequence accumulates its frames (--temporal):
// along a path that stands still its frames are the mean of many jittered
// points per pixel, much nearer to a frame of 4 x 4 points than a frame of
// one point is, and never the one-point frame itself.
TEST(AalRender, ACameraPathSequenceAccumulatesItsPointsByDefault) {
  TempDir dir;
  const fs::path path = dir.path() / "still.txt", out = dir.path() / "still.png";
  std::ofstream(path) << "0 -20000 -20000 6000 0 0 300 40\n1 -20000 -20000 6000 0 0 300 40\n";
  const std::string view = " --size 96x54 -q --sun-azimuth 200 --sun-elevation 20 ";
  ASSERT_EQ(
      render(dir, "-o " + quoted(out) + view + "--camera-path " + quoted(path) + " --frames 2")
          .exitCode,
      0);
  const auto single = [&](const std::string& name, const std::string& options) {
    const fs::path one = dir.path() / name;
    EXPECT_EQ(render(dir, "-o " + quoted(one) + view +
                              "--camera -20000,-20000,6000 --look-at 0,0,300 --fov 40 " + options)
                  .exitCode,
              0);
    return pixelsOf(one);
  };
  const std::vector<uint8_t> accumulated = pixelsOf(dir.path() / "still-0002.png"),
                             one = single("one.png", ""),
                             sixteen = single("sixteen.png", "--supersample 4");
  ASSERT_EQ(accumulated.size(), sixteen.size());
  ASSERT_EQ(one.size(), sixteen.size());
  const auto rms = [&](const std::vector<uint8_t>& a) {
    double sum = 0;
    for (size_t i = 0; i < a.size(); ++i) sum += std::pow(double(a[i]) - double(sixteen[i]), 2);
    return std::sqrt(sum / double(a.size()));
  };
  std::printf("RMS against 4 x 4 points: accumulated %.3f, one point %.3f (8-bit levels)\n",
              rms(accumulated), rms(one));
  EXPECT_LT(rms(accumulated), 0.6 * rms(one));
}

// With ffmpeg installed (optional, Debian's ffmpeg) the PNG frames also
// become OUT.mp4, H.264 with every frame.
TEST(AalRender, SequenceBecomesAnMp4WhenFfmpegIsInstalled) {
  if (std::system("command -v ffmpeg >/dev/null 2>&1 && command -v ffprobe >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "ffmpeg/ffprobe not installed";
  }
  TempDir dir;
  const fs::path out = dir.path() / "lapse.png", mp4 = dir.path() / "lapse.mp4";
  const auto r = render(dir, "-o " + quoted(out) +
                                 " --size 47x27 --time-range 2024-06-21T12:00Z 2024-06-21T20:00Z "
                                 "--frames 5 --fps 10");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  ASSERT_TRUE(fs::exists(mp4)) << r.out;
  const auto probe = test::runShell(
      "ffprobe -v error -count_frames -select_streams v:0 -show_entries "
      "stream=codec_name,nb_read_frames,width,r_frame_rate -of csv=p=0 " +
      quoted(mp4));
  ASSERT_EQ(probe.exitCode, 0) << probe.out;
  // Odd widths are padded to even ones for H.264's 4:2:0.
  EXPECT_NE(probe.out.find("h264,48,10/1,5"), std::string::npos) << probe.out;
}

// The movie goes through a temporary file renamed into place (here with a
// stand-in for ffmpeg that writes its last argument, the output): ffmpeg -y
// wrote OUT.mp4 itself, and a failing run removed an OUT.mp4 it had not
// made.
TEST(AalRender, TheMovieIsWrittenThroughATemporaryAndAFailedOneKeepsTheOld) {
  TempDir dir;
  const fs::path out = dir.path() / "lapse.png", mp4 = dir.path() / "lapse.mp4";
  const fs::path works = dir.path() / "works", fails = dir.path() / "fails";
  std::ofstream(works) << "#!/bin/sh\nfor a; do last=$a; done\necho movie > \"$last\"\n";
  std::ofstream(fails) << "#!/bin/sh\nfor a; do last=$a; done\necho half > \"$last\"\nexit 1\n";
  for (const fs::path& script : {works, fails}) fs::permissions(script, fs::perms::owner_all);
  const std::string args = "-o " + quoted(out) +
                           " --size 16x9 -q --time-range 2024-06-21T12:00Z 2024-06-21T14:00Z "
                           "--frames 2";
  const auto made =
      runTool("aal-render", quoted(kDem) + " " + args,
              "AAL_FFMPEG=" + quoted(works) + " AAL_CACHE_DIR=" + quoted(dir.path() / "cache"));
  ASSERT_EQ(made.exitCode, 0) << made.out;
  std::ifstream in(mp4);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()),
            "movie\n");
  std::ofstream(mp4) << "the old movie";
  const auto failed =
      runTool("aal-render", quoted(kDem) + " " + args,
              "AAL_FFMPEG=" + quoted(fails) + " AAL_CACHE_DIR=" + quoted(dir.path() / "cache"));
  EXPECT_EQ(failed.exitCode, 1) << failed.out;
  EXPECT_NE(failed.out.find("failed to encode"), std::string::npos) << failed.out;
  std::ifstream old(mp4);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(old), std::istreambuf_iterator<char>()),
            "the old movie");
  for (const auto& entry : fs::directory_iterator(dir.path())) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
  }
}

TEST(AalRender, BadSequenceOptionsExitWithTwoAndSayWhich) {
  TempDir dir;
  const fs::path path = dir.path() / "flight.txt";
  std::ofstream(path) << "0 -20000 -20000 6000 0 0 300\n";
  const std::string o = "-o " + quoted(dir.path() / "x.png") + " --size 32x18 ";
  const std::string p = " --camera-path " + quoted(path);
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {"--frames 3", "--frames"},
           {p, "--frames"},
           {p + " --frames 0", "--frames"},
           {"--time-range 2024-06-21T12:00Z 2024-06-21T10:00Z --frames 2", "after START"},
           {"--time-range 2024-06-21T12:00Z noon --frames 2", "--time-range"},
           {"--time-range 2024-06-21T12:00Z --frames 2", "--time-range"},
           {"--time-range 2024-06-21T12:00Z 2024-06-21T14:00Z --frames 2 --time "
            "2024-06-21T12:00Z",
            "--time-range"},
           {p + " --frames 2 --camera 1,2,3", "--camera-path"},
           {p + " --frames 2 --mode reference", "--mode reference"},
           {"--temporal on", "--temporal"},
           {p + " --frames 2 --temporal sometimes", "--temporal"},
           {" --camera-path " + quoted(dir.path() / "none.txt") + " --frames 2", "none.txt"}}) {
    const auto r = render(dir, o + args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(says), std::string::npos) << args << "\n" << r.out;
  }
}

// Water only where the user asks: a georeferenced DEM does not paint every
// height <= 0 m as a lake.
TEST(AalRender, WaterOnlyAtTheLevelAsked) {
  TempDir dir;
  const auto shot = [&](const std::string& name, const std::string& extra) {
    const fs::path out = dir.path() / name;
    const auto r = render(dir, "-o " + quoted(out) + " --size 64x36 " + extra);
    EXPECT_EQ(r.exitCode, 0) << r.out;
    return pixelsOf(out);
  };
  const std::vector<uint8_t> dry = shot("dry.png", ""), low = shot("low.png", "--water-level 100"),
                             high = shot("high.png", "--water-level 5000");
  ASSERT_FALSE(dry.empty());
  EXPECT_EQ(low, dry);  // below the lowest height (~250 m): nothing changes
  // Every terrain pixel is water now (the terrain fills 36 % of this framed
  // view; the sky keeps its colour).
  size_t darker = 0, pixels = dry.size() / 4;
  for (size_t p = 0; p < pixels; ++p) {
    const int before = dry[4 * p] + dry[4 * p + 1] + dry[4 * p + 2];
    const int after = high[4 * p] + high[4 * p + 1] + high[4 * p + 2];
    darker += after + 24 < before;
  }
  EXPECT_GT(darker, pixels / 10);
  const auto r = render(dir, "-o " + quoted(dir.path() / "x.png") + " --water-level nan");
  EXPECT_EQ(r.exitCode, 2) << r.out;
}

// --background transparent gives alpha 0 where there is no terrain
// (the PNG keeps the sky's colour there), alpha 255 on the terrain, the same
// RGB as the default; the default camera frames the DEM (its diamond covers
// 36 % of the frame, 14 % with the older camera that looked at the box's
// centre). Bad values and the CPU paths are
// refused with exit 2.
TEST(AalRender, TransparentBackgroundHasAlphaZeroOffTheTerrain) {
  TempDir dir;
  const fs::path sky = dir.path() / "sky.png", clear = dir.path() / "clear.png";
  ASSERT_EQ(render(dir, "-o " + quoted(sky) + " --size 64x36 -q").exitCode, 0);
  const auto r = render(dir, "-o " + quoted(clear) + " --size 64x36 -q --background transparent");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  ASSERT_EQ(specOf(clear).nchannels, 4);
  const std::vector<uint8_t> a = pixelsOf(sky), b = pixelsOf(clear);
  ASSERT_EQ(a.size(), 64u * 36 * 4);
  ASSERT_EQ(b.size(), a.size());
  size_t terrain = 0;
  for (size_t p = 0; p < a.size() / 4; ++p) {
    for (int c = 0; c < 3; ++c) ASSERT_EQ(a[4 * p + c], b[4 * p + c]) << p;
    EXPECT_EQ(a[4 * p + 3], 255);
    ASSERT_TRUE(b[4 * p + 3] == 0 || b[4 * p + 3] == 255) << p;
    terrain += b[4 * p + 3] == 255;
  }
  EXPECT_EQ(b[3], 0);                         // top-left corner: beyond the DEM
  EXPECT_EQ(b[4 * (18 * 64 + 32) + 3], 255);  // the centre: terrain
  EXPECT_GT(terrain, a.size() / 4 * 3 / 10);  // framed: 36 %, 14 % with the older camera
  EXPECT_LT(terrain, a.size() / 4 * 9 / 10);
  for (const std::string& bad : {std::string("--background purple"),
                                 std::string("--background transparent --mode reference")}) {
    const auto e = render(dir, "-o " + quoted(dir.path() / "x.png") + " --size 32x18 " + bad);
    EXPECT_EQ(e.exitCode, 2) << bad << "\n" << e.out;
    EXPECT_NE(e.out.find("--background"), std::string::npos) << e.out;
  }
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

TEST(AalRender, ReferenceModeRaytracesWithoutAVulkanDevice) {
  // The CPU reference needs neither a device nor an aperture map.
  TempDir dir;
  const fs::path out = dir.path() / "ref.exr";
  const auto r =
      runTool("aal-render",
              quoted(kDem) + " -o " + quoted(out) +
                  " --mode reference --size 40x24 --reference-sky-rays 4 "
                  "--reference-sun-rays 1 --albedo-value 0.3",
              "AAL_CACHE_DIR=" + quoted(dir.path() / "cache") +
                  " VK_ICD_FILENAMES=/nonexistent.json VK_DRIVER_FILES=/nonexistent.json");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(specOf(out).width, 40);
  EXPECT_FALSE(fs::exists(dir.path() / "cache")) << "nothing was baked";
}

TEST(AalRender, CompareWritesEveryModeItsErrorMapAndATable) {
  TempDir dir;
  const fs::path folder = dir.path() / "cmp";
  const auto r = render(dir, "--compare " + quoted(folder) +
                                 " --size 48x27 --reference-sky-rays 16 --reference-sun-rays 4");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  for (const char* name :
       {"reference.exr", "reference.png", "approx.png", "approx-error.png", "exact.png",
        "approx-without-w.png", "baseline-lambert.png", "baseline-ao-error.png", "errors.csv"}) {
    EXPECT_TRUE(fs::exists(folder / name)) << name;
  }
  EXPECT_NE(r.out.find("relative RMSE"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("baseline-ao"), std::string::npos) << r.out;
}

// --compare with --camera-path: the still images are the path's first
// frame, and errors.csv gains each mode's shimmer along the pan, its ratio
// to the reference's, its mean error along the pan and a row for the
// reference; a pan needs three frames for a second difference, and a
// --time-range is no pan.
TEST(AalRender, CompareAlongACameraPathAddsTheShimmer) {
  TempDir dir;
  const fs::path folder = dir.path() / "cmp", path = dir.path() / "pan.txt";
  std::ofstream(path) << "0 12000 -15000 6000 0 0 500\n1 12100 -15000 6000 100 0 500\n";
  const std::string common = "--compare " + quoted(folder) +
                             " --size 32x18 --reference-sky-rays 4 --reference-sun-rays 1 "
                             "--reference-subpixels 1 --camera-path " +
                             quoted(path);
  const auto r = render(dir, common + " --frames 3");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("shimmer"), std::string::npos) << r.out;
  std::ifstream csv(folder / "errors.csv");
  std::string header, line, last;
  std::getline(csv, header);
  EXPECT_EQ(header,
            "mode,relative_rmse,mean_relative_error,shimmer,shimmer_vs_reference,"
            "pan_relative_rmse");
  int rows = 0;
  while (std::getline(csv, line)) {
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 5) << line;
    last = line;
    ++rows;
  }
  EXPECT_EQ(rows, 6);  // approx, exact, approx-without-w, two baselines, reference
  EXPECT_EQ(last.rfind("reference,0,0,", 0), 0u) << last;
  EXPECT_NE(last.find(",1.000000,0"), std::string::npos) << last;
  for (const auto& [args, says] : std::vector<std::pair<std::string, std::string>>{
           {common + " --frames 2", "--frames 3"},
           {"--compare " + quoted(folder) +
                " --time-range 2024-06-21T10:00Z 2024-06-21T12:00Z "
                "--frames 3",
            "--time-range"}}) {
    const auto bad = render(dir, args);
    EXPECT_EQ(bad.exitCode, 2) << args << "\n" << bad.out;
    EXPECT_NE(bad.out.find(says), std::string::npos) << args << "\n" << bad.out;
  }
}

// --horizons (aal-bake --horizons): the horizon mode renders with them,
// --compare adds it, and without them, or with another DEM's, exit 2.
TEST(AalRender, HorizonModeTakesTheBakesDirectionalHorizons) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr", horizons = dir.path() / "a.horizons";
  ASSERT_EQ(test::bakeWithHorizons(kDem, map, horizons), 0);
  const std::string common = "--aperture " + quoted(map) + " --size 64x36 ";
  const auto r = render(dir, common + "--horizons " + quoted(horizons) + " --mode horizon -o " +
                                 quoted(dir.path() / "h.png"));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(specOf(dir.path() / "h.png").width, 64);
  const auto c = render(dir, common + "--horizons " + quoted(horizons) + " --compare " +
                                 quoted(dir.path() / "cmp") +
                                 " --reference-sky-rays 16 --reference-sun-rays 4");
  ASSERT_EQ(c.exitCode, 0) << c.out;
  EXPECT_TRUE(fs::exists(dir.path() / "cmp" / "horizon-error.png"));
  EXPECT_NE(c.out.find("horizon"), std::string::npos) << c.out;
  // Several horizon maps: one reference, a horizon-STEM mode for each; only
  // --compare takes more than one.
  const fs::path four = dir.path() / "four.horizons";
  ASSERT_EQ(runTool("aal-bake", quoted(kDem) + " -o " + quoted(dir.path() / "b.exr") +
                                    " --horizon-directions 16 --horizon-bits 4 --horizons " +
                                    quoted(four) + " -q")
                .exitCode,
            0);
  const auto both = render(dir, common + "--horizons " + quoted(horizons) + " --horizons " +
                                    quoted(four) + " --compare " + quoted(dir.path() / "cmp2") +
                                    " --reference-sky-rays 16 --reference-sun-rays 4");
  ASSERT_EQ(both.exitCode, 0) << both.out;
  EXPECT_TRUE(fs::exists(dir.path() / "cmp2" / "horizon-a-error.png"));
  EXPECT_TRUE(fs::exists(dir.path() / "cmp2" / "horizon-four-error.png"));
  const auto twice =
      render(dir, common + "--horizons " + quoted(horizons) + " --horizons " + quoted(four) +
                      " --mode horizon -o " + quoted(dir.path() / "t.png"));
  EXPECT_EQ(twice.exitCode, 2) << twice.out;
  EXPECT_FALSE(fs::exists(dir.path() / "t.png"));

  const auto missing = render(dir, common + "--mode horizon -o " + quoted(dir.path() / "m.png"));
  EXPECT_EQ(missing.exitCode, 2) << missing.out;
  EXPECT_NE(missing.out.find("--horizons"), std::string::npos) << missing.out;
  const fs::path other = dir.path() / "other.tif", otherHorizons = dir.path() / "o.horizons";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(other) + " --size 32").exitCode, 0);
  ASSERT_EQ(runTool("aal-bake", quoted(other) + " -o " + quoted(dir.path() / "o.exr") +
                                    " --horizons " + quoted(otherHorizons) + " -q")
                .exitCode,
            0);
  const auto foreign = render(dir, common + "--horizons " + quoted(otherHorizons) +
                                       " --mode horizon -o " + quoted(dir.path() / "f.png"));
  EXPECT_EQ(foreign.exitCode, 2) << foreign.out;
  const auto notAMap = render(dir, common + "--horizons " + quoted(other) + " --mode horizon -o " +
                                       quoted(dir.path() / "n.png"));
  EXPECT_EQ(notAMap.exitCode, 2) << notAMap.out;
  EXPECT_FALSE(fs::exists(dir.path() / "m.png") || fs::exists(dir.path() / "f.png") ||
               fs::exists(dir.path() / "n.png"));
}

TEST(AalRender, SupersampleAveragesItsPointsIntoTheAskedSize) {
  // 3 x 3 points per pixel at 64 x 36 against one point per pixel at
  // 192 x 108 averaged over each 3 x 3 block by hand: the colour over the
  // block's terrain (alpha unassociated), the alpha its coverage. They differ
  // by the tone map taken after the mean instead of before it, and rounding.
  TempDir dir;
  const fs::path big = dir.path() / "big.png", smooth = dir.path() / "smooth.png";
  const std::string common = " -q --background transparent";
  ASSERT_EQ(render(dir, "-o " + quoted(big) + " --size 192x108" + common).exitCode, 0);
  const auto r = render(dir, "-o " + quoted(smooth) + " --size 64x36 --supersample 3" + common);
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const std::vector<uint8_t> a = pixelsOf(big), b = pixelsOf(smooth);
  ASSERT_EQ(a.size(), 192u * 108 * 4);
  ASSERT_EQ(b.size(), 64u * 36 * 4);
  double difference = 0, worst = 0;
  size_t partial = 0;
  for (size_t y = 0; y < 36; ++y) {
    for (size_t x = 0; x < 64; ++x) {
      double covered[3] = {}, all[3] = {}, alpha = 0;
      for (size_t j = 0; j < 3; ++j) {
        for (size_t i = 0; i < 3; ++i) {
          const uint8_t* p = &a[4 * ((3 * y + j) * 192 + 3 * x + i)];
          for (int c = 0; c < 3; ++c) {
            covered[c] += p[3] / 255.0 * p[c];
            all[c] += p[c];
          }
          alpha += p[3] / 255.0;
        }
      }
      const uint8_t* q = &b[4 * (y * 64 + x)];
      for (int c = 0; c < 3; ++c) {
        const double expected = alpha > 0 ? covered[c] / alpha : all[c] / 9;
        difference += std::abs(q[c] - expected);
        worst = std::max(worst, std::abs(q[c] - expected));
      }
      EXPECT_NEAR(q[3], 255 * alpha / 9, 0.51) << x << "," << y;
      partial += q[3] > 0 && q[3] < 255;
    }
  }
  EXPECT_LT(difference / (3.0 * 64 * 36), 0.5);
  EXPECT_LT(worst, 3.0);
  // The silhouette against the sky partly covers pixels.
  EXPECT_GT(partial, 20u);
}

TEST(AalRender, ReferenceAndCompareRefuseWhatTheyCannotDo) {
  TempDir dir;
  const fs::path albedo = dir.path() / "albedo.png";
  ASSERT_EQ(test::runShell("oiiotool --create 8x8 3 -o " + quoted(albedo)).exitCode, 0);
  const std::string out = " -o " + quoted(dir.path() / "x.png");
  const std::vector<std::pair<std::string, std::string>> cases = {
      {out + " --mode reference --albedo " + quoted(albedo), "constant albedo"},
      {"--compare " + quoted(dir.path() / "c") + " --albedo " + quoted(albedo), "constant albedo"},
      {"--compare " + quoted(dir.path() / "c") + " --mode reference", "leave out --mode reference"},
      {out + " --compare " + quoted(dir.path() / "c"), "one of them"},
      {"--size 8x8", "one of them"},
      {out + " --mode reference --supersample 2", "--reference-subpixels"},
  };
  for (const auto& [args, message] : cases) {
    const auto r = render(dir, args);
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
}

// A truncated cache entry must not make every later render of its DEM exit
// 2 until it is deleted by hand: it is rebaked and replaced,
// with one warning line naming it.
TEST(AalRender, ADamagedCacheEntryIsRebakedWithAWarning) {
  TempDir dir;
  const fs::path first = dir.path() / "a.png";
  ASSERT_EQ(render(dir, "-o " + quoted(first) + " --size 64x36").exitCode, 0);
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(dir.path() / "cache")) entries.push_back(e.path());
  ASSERT_EQ(entries.size(), 1u);
  const fs::path entry = entries[0];
  fs::resize_file(entry, fs::file_size(entry) / 2);
  const fs::path second = dir.path() / "b.png";
  const auto r = render(dir, "-o " + quoted(second) + " --size 64x36 -q");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.out.rfind("warning: rebaking the cached aperture map " + entry.string(), 0), 0u)
      << r.out;
  EXPECT_NE(r.out.find("truncated or corrupt"), std::string::npos) << r.out;
  EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
  EXPECT_EQ(fs::file_size(first), fs::file_size(second));
  // Replaced: the next render uses it without a word.
  const auto again = render(dir, "-o " + quoted(second) + " --size 64x36 -q");
  ASSERT_EQ(again.exitCode, 0) << again.out;
  EXPECT_EQ(again.out, "");
}

// A map given with --aperture whose pixels do not match the checksum in its
// header is refused (exit 2), naming it.
TEST(AalRender, RefusesAnApertureMapWhosePixelsDoNotMatchTheirChecksum) {
  TempDir dir;
  const fs::path map = dir.path() / "map.exr";
  ASSERT_EQ(runTool("aal-bake",
                    quoted(kDem) + " -o " + quoted(map) + " --azimuths 16 --compression none -q")
                .exitCode,
            0);
  // Uncompressed, the file ends with the last texel's red half: flip a
  // mantissa bit of it (the map still decodes).
  {
    std::fstream file(map, std::ios::binary | std::ios::in | std::ios::out);
    file.seekg(-2, std::ios::end);
    const char byte = static_cast<char>(file.get() ^ 1);
    file.seekp(-2, std::ios::end);
    file.put(byte);
  }
  const auto r =
      render(dir, "-o " + quoted(dir.path() / "x.png") + " --size 64x36 --aperture " + quoted(map));
  EXPECT_EQ(r.exitCode, 2) << r.out;
  EXPECT_NE(r.out.find(map.string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("checksum"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir.path() / "x.png"));
}

}  // namespace
}  // namespace aal
