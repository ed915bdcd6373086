// Command-line contract of aal-view: scripted flights under Xvfb on lavapipe
// with validation on, background bakes, dropped files, no display, bad input.
#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdlib>

#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runShell;
using test::runTool;
using test::TempDir;

const fs::path kDem = fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif";

// aal-view under xvfb-run with this test's own aperture cache (run_tool.h).
test::ToolResult view(const TempDir& dir, const std::string& args) {
  return test::runViewer(args, "AAL_CACHE_DIR=" + quoted(dir.path() / "cache"));
}

size_t filesIn(const fs::path& folder) {
  size_t n = 0;
  std::error_code ignored;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(folder, ignored)) ++n;
  return n;
}

struct Picture {
  int width = 0, height = 0;
  std::vector<unsigned char> rgba;
};

Picture readPng(const fs::path& path) {
  Picture p;
  auto in = OIIO::ImageInput::open(path.string());
  if (!in) return p;
  p.width = in->spec().width;
  p.height = in->spec().height;
  p.rgba.resize(size_t(p.width) * p.height * 4);
  in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, p.rgba.data());
  return p;
}

// Standard deviation of the green channel over a block of rows.
double greenSpread(const Picture& p, int firstRow, int endRow) {
  double sum = 0, sum2 = 0;
  size_t n = 0;
  for (int y = firstRow; y < endRow; ++y) {
    for (int x = 0; x < p.width; ++x) {
      const double g = p.rgba[(size_t(y) * p.width + x) * 4 + 1];
      sum += g;
      sum2 += g * g;
      ++n;
    }
  }
  const double mean = sum / n;
  return std::sqrt(std::max(0.0, sum2 / n - mean * mean));
}

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A flight towards the centre of jacksboro (403 x 344 texels of ~75 x 92 m,
// heights 236..1076 m) from the south-west.
constexpr const char* kPath =
    "# time  position              look-at\n"
    "0   -22000 -18000 9000   0 0 500\n"
    "1   -15000 -12000 6000   0 0 500\n";

TEST(AalView, ScriptedFlightShowsTerrainWithoutValidationMessages) {
  TempDir dir;
  const fs::path path = dir.path() / "path.txt", shot = dir.path() / "shot.png";
  writeText(path, kPath);
  const auto r = view(dir, quoted(kDem) + " --size 320x240 --frames 4 --camera-path " +
                               quoted(path) + " --screenshot " + quoted(shot) + " --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_EQ(r.out.find("vulkan validation"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("validation on, 0 messages"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames     4"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("present    fifo (vsync)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("gpu terrain"), std::string::npos) << r.out;
  // Where the main thread's time went (a CPU device shades while it waits).
  EXPECT_NE(r.out.find("main thread, mean ms per frame: wait for the slot's frame"),
            std::string::npos)
      << r.out;
  // The aperture map was baked in the background and cached, with its
  // directional horizons beside it.
  EXPECT_NE(r.out.find("aperture map ready"), std::string::npos) << r.out;
  EXPECT_EQ(filesIn(dir.path() / "cache"), 2u);

  const Picture p = readPng(shot);
  ASSERT_EQ(p.width, 320);
  ASSERT_EQ(p.height, 240);
  // Terrain fills the lower part of the view: many distinct colours with
  // real contrast, not a blank, constant or sky-only picture.
  std::set<unsigned> colours;
  for (size_t i = 0; i < p.rgba.size(); i += 4) {
    colours.insert(p.rgba[i] << 16 | p.rgba[i + 1] << 8 | p.rgba[i + 2]);
  }
  EXPECT_GT(colours.size(), 200u);
  EXPECT_GT(greenSpread(p, 120, 240), 4.0) << "flat colour where the terrain should be";
  // Terrain is greener than the sky at the top.
  double topGreenMinusBlue = 0, bottomGreenMinusBlue = 0;
  for (int x = 0; x < p.width; ++x) {
    const size_t top = size_t(x) * 4, bottom = (size_t(239) * p.width + x) * 4;
    topGreenMinusBlue += double(p.rgba[top + 1]) - p.rgba[top + 2];
    bottomGreenMinusBlue += double(p.rgba[bottom + 1]) - p.rgba[bottom + 2];
  }
  EXPECT_GT(bottomGreenMinusBlue, topGreenMinusBlue) << "no terrain at the bottom";
}

// "drawn N frames, M idle iterations" of --stats.
std::pair<int, int> drawnAndIdle(const std::string& out) {
  const size_t at = out.find("drawn      ");
  if (at == std::string::npos) return {-1, -1};
  int drawn = -1, idle = -1;
  std::sscanf(out.c_str() + at, "drawn %d frames, %d idle", &drawn, &idle);
  return {drawn, idle};
}

TEST(AalView, AnIdleViewerDrawsNothing) {
  TempDir dir;
  // No input under Xvfb and nothing animated: after the first frames the
  // viewer waits for events instead of drawing the same picture again.
  const auto r = view(dir, quoted(kDem) + " --size 320x240 --timeout 4 --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const auto [drawn, idle] = drawnAndIdle(r.out);
  EXPECT_GE(drawn, 1) << r.out;
  // The background bake's progress bar redraws a few times a second until
  // the map is ready (jacksboro: well under a second, a few under the
  // sanitizers), then nothing; drawing all along would be 25 frames or more
  // in 4 s even under the sanitizers.
  EXPECT_LE(drawn, 12) << r.out;
  EXPECT_GE(idle, 5) << r.out;
}

TEST(AalView, DynamicResolutionDrawsFewerPixelsWhileTheViewMoves) {
  TempDir dir;
  const fs::path path = dir.path() / "path.txt", shot = dir.path() / "shot.png";
  writeText(path, kPath);
  // A target no machine meets: every moving frame at the smallest scale; the
  // screenshot (the last frame) at full resolution.
  const auto r =
      view(dir, quoted(kDem) + " --size 320x240 --frames 12 --camera-path " + quoted(path) +
                    " --target-fps 1000 --screenshot " + quoted(shot) + " --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("validation on, 0 messages"), std::string::npos) << r.out;
  int reduced = -1;
  const size_t at = r.out.find("resolution ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const size_t comma = r.out.find(", ", at);
  ASSERT_NE(comma, std::string::npos) << r.out;
  std::sscanf(r.out.c_str() + comma, ", %d frames reduced", &reduced);
  EXPECT_GE(reduced, 8) << r.out;
  EXPECT_NE(r.out.find("target 1000 fps"), std::string::npos) << r.out;
  const Picture p = readPng(shot);
  EXPECT_EQ(p.width, 320);
  EXPECT_GT(greenSpread(p, 120, 240), 4.0) << "flat colour where the terrain should be";
  // Off by default in scripted runs.
  const auto plain = view(
      dir, quoted(kDem) + " --size 320x240 --frames 3 --camera-path " + quoted(path) + " --stats");
  ASSERT_EQ(plain.exitCode, 0) << plain.out;
  EXPECT_NE(plain.out.find("0 frames reduced (target 0 fps: off)"), std::string::npos) << plain.out;
}

// --temporal on: the frames drawn smaller are rebuilt at full resolution
// (the resolve pass in place of the upscale), validation-clean; off (as
// auto is on lavapipe) scales them up.
TEST(AalView, TemporalReconstructionRebuildsTheFramesDrawnSmaller) {
  TempDir dir;
  const fs::path path = dir.path() / "path.txt";
  writeText(path, kPath);
  const std::string run = quoted(kDem) + " --size 320x240 --frames 8 --camera-path " +
                          quoted(path) + " --target-fps 1000 --stats --temporal ";
  const auto on = view(dir, run + "on");
  ASSERT_EQ(on.exitCode, 0) << on.out;
  EXPECT_NE(on.out.find("validation on, 0 messages"), std::string::npos) << on.out;
  EXPECT_NE(on.out.find("gpu resolve"), std::string::npos) << on.out;
  EXPECT_EQ(on.out.find("gpu upscale"), std::string::npos) << on.out;
  const auto off = view(dir, run + "off");
  ASSERT_EQ(off.exitCode, 0) << off.out;
  EXPECT_NE(off.out.find("gpu upscale"), std::string::npos) << off.out;
  EXPECT_EQ(off.out.find("gpu resolve"), std::string::npos) << off.out;
  const auto wrong = view(dir, run + "sometimes");
  EXPECT_EQ(wrong.exitCode, 2) << wrong.out;
}

TEST(AalView, UsesTheCachedApertureMapOnTheSecondRunAndPresentsWithoutVsync) {
  TempDir dir;
  ASSERT_EQ(view(dir, quoted(kDem) + " --size 160x120 --frames 1").exitCode, 0);
  const auto again = view(dir, quoted(kDem) + " --size 160x120 --frames 1 --no-vsync --stats");
  ASSERT_EQ(again.exitCode, 0) << again.out;
  // Without vsync: MAILBOX or IMMEDIATE (lavapipe's X11 surfaces offer both).
  EXPECT_EQ(again.out.find("present    fifo"), std::string::npos) << again.out;
  EXPECT_EQ(again.out.find("aperture map ready"), std::string::npos) << again.out;
  EXPECT_EQ(filesIn(dir.path() / "cache"), 2u);  // the map and its horizons
}

TEST(AalView, ClosingDuringABakeCancelsItAndCachesNothing) {
  TempDir dir;
  // 1024^2 at 1024 azimuths bakes for many seconds even on a fast machine;
  // the window closes after one, and cancelling waits for at most one azimuth.
  const fs::path dem = dir.path() / "big.tif";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(dem) + " --size 1024").exitCode, 0);
  const auto r = view(dir, quoted(dem) + " --size 160x120 --azimuths 1024 --timeout 1 --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  // The terrain was on screen (baseline shading) while the bake ran.
  EXPECT_EQ(r.out.find("baking     0 frames"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames drawn while the aperture map was baked"), std::string::npos);
  EXPECT_NE(r.out.find("cancelled, nothing cached"), std::string::npos) << r.out;
  EXPECT_EQ(filesIn(dir.path() / "cache"), 0u) << "a partial cache file was left";
}

TEST(AalView, AnUnreadableDroppedDemKeepsTheTerrain) {
  TempDir dir;
  const fs::path shot = dir.path() / "shot.png";
  const auto r =
      view(dir, quoted(kDem) + " --size 160x120 --frames 2 --drop " +
                    quoted(dir.path() / "missing.tif") + " --screenshot " + quoted(shot));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("cannot open"), std::string::npos) << r.out;
  const Picture p = readPng(shot);
  ASSERT_EQ(p.width, 160);
  EXPECT_GT(greenSpread(p, 0, 120), 2.0);
}

TEST(AalView, ADroppedDemReplacesTheTerrain) {
  TempDir dir;
  // The first DEM's bake must still run when the second is dropped after
  // the first frame: 2048^2 takes ~2 s to bake here (jacksboro, ~0.05 s
  // since the AVX2 sweep, sometimes finished first and was cached).
  const fs::path first = dir.path() / "big.tif", dem = dir.path() / "small.tif";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(first) + " --size 2048").exitCode, 0);
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(dem) + " --size 96").exitCode, 0);
  const auto r =
      view(dir, quoted(first) + " --size 160x120 --frames 2 --stats --drop " + quoted(dem));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("opened"), std::string::npos) << r.out;
  // Read on a thread and sent a share a frame while the first DEM was drawn.
  EXPECT_NE(r.out.find("frames drawn while a dropped DEM was read and built"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("shown after"), std::string::npos) << r.out;
  // The first DEM's bake was cancelled when the second replaced it: the
  // second's map and horizons.
  EXPECT_EQ(filesIn(dir.path() / "cache"), 2u);
}

// DEMs dropped together: each is read in turn, a drop during a read waits
// for it, and the last is the one shown.
TEST(AalView, DemsDroppedTogetherShowTheLast) {
  TempDir dir;
  const fs::path a = dir.path() / "a.tif", b = dir.path() / "b.tif";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(a) + " --size 96").exitCode, 0);
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(b) + " --size 80").exitCode, 0);
  // The first DEM's map cached before (else its bake, cancelled by the drop
  // when slow, as under the sanitizers, may cache nothing).
  ASSERT_EQ(view(dir, quoted(kDem) + " --size 160x120 --frames 1").exitCode, 0);
  ASSERT_EQ(filesIn(dir.path() / "cache"), 2u);
  const auto r = view(dir, quoted(kDem) + " --size 160x120 --frames 2 --stats --drop " + quoted(a) +
                               " --drop " + quoted(b));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("opening " + b.string() + " after " + a.string()), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("opened " + b.string()), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("opened " + a.string()), std::string::npos) << r.out;
  // Only the shown DEM was baked: its map and horizons.
  EXPECT_EQ(r.out.find("shown after", r.out.find("shown after") + 1), std::string::npos)
      << "one drop shown";
  EXPECT_EQ(filesIn(dir.path() / "cache"), 4u) << "the first DEM's and the last drop's alone";
}

// A dropped DEM with a cached map is shown with it (read on the opening's
// thread, sent with the scene), its cached horizons read and sent after it:
// in the horizon mode the same picture as the DEM opened at start.
TEST(AalView, ADroppedDemWithACachedMapShowsIt) {
  TempDir dir;
  const fs::path atStart = dir.path() / "start.png", dropped = dir.path() / "dropped.png";
  const std::string args = quoted(kDem) +
                           " --size 160x120 --frames 2 --stats --sun-azimuth 250 "
                           "--sun-elevation 12 --mode-after 1:horizon";
  // The first run bakes and caches the map; the second drops the same DEM.
  const auto first = view(dir, args + " --screenshot " + quoted(atStart));
  ASSERT_EQ(first.exitCode, 0) << first.out;
  const auto second =
      view(dir, args + " --drop " + quoted(kDem) + " --screenshot " + quoted(dropped));
  ASSERT_EQ(second.exitCode, 0) << second.out;
  EXPECT_NE(second.out.find("its aperture map from the cache"), std::string::npos) << second.out;
  EXPECT_NE(second.out.find("baking     0 frames"), std::string::npos) << second.out;
  EXPECT_EQ(second.out.find("no horizon mode"), std::string::npos) << second.out;
  const Picture a = readPng(atStart), b = readPng(dropped);
  ASSERT_EQ(a.width, 160);
  ASSERT_EQ(b.width, 160);
  EXPECT_TRUE(a.rgba == b.rgba) << "the dropped DEM's picture differs";
  EXPECT_GT(greenSpread(b, 0, 120), 2.0);
}

TEST(AalView, WithoutADisplayItPointsToAalRender) {
  const auto r = runTool("aal-view", quoted(kDem) + " --frames 1", "-u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_TRUE(r.exitCode == 1 || r.exitCode == 2) << r.exitCode << r.out;
  EXPECT_NE(r.out.find("aal-render"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("display"), std::string::npos) << r.out;
}

TEST(AalView, BadCommandLineExitsWithTwoBeforeOpeningAWindow) {
  TempDir dir;
  const fs::path bad = dir.path() / "bad.txt";
  writeText(bad, "0 1 2 3 4 5\n");
  const std::string dem = quoted(kDem);
  for (const std::string& args :
       {quoted(dir.path() / "missing.tif"), dem + " --frames 0", dem + " --frames -3",
        dem + " --frames 2 --camera-path " + quoted(bad),
        dem + " --frames 2 --camera-path " + quoted(dir.path() / "none.txt"),
        dem + " --frames 2 --screenshot " + quoted(dir.path() / "x.jpg"),
        dem + " --screenshot " + quoted(dir.path() / "x.png"), dem + " --size 0x10",
        dem + " --mode magic", dem + " --sun-azimuth 10", dem + " --exaggeration 0",
        dem + " --exaggeration -2", dem + " --exaggeration 1000",
        dem + " --aperture " + quoted(dir.path() / "missing.exr")}) {
    // No display: input errors must be found before a window is needed.
    const auto r = runTool("aal-view", args, "-u DISPLAY -u WAYLAND_DISPLAY");
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_EQ(r.out.find("aal-render"), std::string::npos) << args << "\n" << r.out;
  }
  // A screenshot that would overwrite an input.
  const fs::path png = dir.path() / "dem.png";
  fs::copy_file(kDem, dir.path() / "dem.tif");
  fs::create_symlink(dir.path() / "dem.tif", png);
  const auto alias = runTool("aal-view", quoted(png) + " --frames 1 --screenshot " + quoted(png),
                             "-u DISPLAY -u WAYLAND_DISPLAY");
  EXPECT_EQ(alias.exitCode, 2) << alias.out;
  EXPECT_NE(alias.out.find("is the input DEM"), std::string::npos) << alias.out;
  const auto frames = runTool("aal-view", dem + " --frames 0", "-u DISPLAY");
  EXPECT_NE(frames.out.find("--frames"), std::string::npos) << frames.out;
  const auto path =
      runTool("aal-view", dem + " --frames 2 --camera-path " + quoted(bad), "-u DISPLAY");
  EXPECT_NE(path.out.find("line 1"), std::string::npos) << path.out;
}

// Bad input, not a failed system: exit 2, not 1.
TEST(AalView, ATinyDemAndAMissingDeviceExitWithTwo) {
  TempDir dir;
  const fs::path one = dir.path() / "one.asc";
  writeText(one, "ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 5\n7\n");
  const auto tiny = view(dir, quoted(one) + " --frames 2");
  EXPECT_EQ(tiny.exitCode, 2) << tiny.out;
  EXPECT_NE(tiny.out.find("1 x 1 texels have no surface to render"), std::string::npos) << tiny.out;
  const auto device = view(dir, quoted(kDem) + " --frames 2 --device 9");
  EXPECT_EQ(device.exitCode, 2) << device.out;
  EXPECT_NE(device.out.find("--device 9 is not available"), std::string::npos) << device.out;
}

TEST(AalView, HelpExplainsTheControls) {
  const auto r = runTool("aal-view", "--help");
  ASSERT_EQ(r.exitCode, 0);
  for (const char* text : {"right mouse", "W A S D", "Shift", "mouse wheel", "F12", "orbit",
                           "--camera-path", "--frames", "--screenshot", "aal-render"}) {
    EXPECT_NE(r.out.find(text), std::string::npos) << text;
  }
}

// The window hooks (--resize-after, --minimise-after, --toggle-vsync-after)
// stand in for the user: they drive the paths that follow the window. Each
// run has a --timeout so that a viewer that stopped drawing ends (with fewer
// frames than asked, which the checks catch) instead of hanging the test.

// Terrain as in ScriptedFlightShowsTerrainWithoutValidationMessages: many
// colours, contrast in the lower half, greener at the bottom than the sky.
void expectTerrain(const Picture& p) {
  std::set<unsigned> colours;
  for (size_t i = 0; i < p.rgba.size(); i += 4) {
    colours.insert(p.rgba[i] << 16 | p.rgba[i + 1] << 8 | p.rgba[i + 2]);
  }
  EXPECT_GT(colours.size(), 200u);
  EXPECT_GT(greenSpread(p, p.height / 2, p.height), 4.0) << "flat colour instead of terrain";
  double top = 0, bottom = 0;
  for (int x = 0; x < p.width; ++x) {
    const size_t t = size_t(x) * 4, b = (size_t(p.height - 1) * p.width + x) * 4;
    top += double(p.rgba[t + 1]) - p.rgba[t + 2];
    bottom += double(p.rgba[b + 1]) - p.rgba[b + 2];
  }
  EXPECT_GT(bottom, top) << "no terrain at the bottom";
}

TEST(AalView, ResizingMidFlightRecreatesTheSwapchainAndRenderer) {
  TempDir dir;
  const fs::path path = dir.path() / "path.txt", shot = dir.path() / "shot.png";
  writeText(path, kPath);
  const auto r = view(dir, quoted(kDem) +
                               " --size 320x240 --frames 5 --resize-after 2:400x300 --timeout 30"
                               " --camera-path " +
                               quoted(path) + " --screenshot " + quoted(shot) + " --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;  // 1 on any validation message
  EXPECT_NE(r.out.find("validation on, 0 messages"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("resizing the window to 400x300"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames     5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("size       400x300"), std::string::npos) << r.out;
  // The screenshot has the renderer's size: still 320 x 240 had only the
  // swapchain followed the window.
  const Picture p = readPng(shot);
  ASSERT_EQ(p.width, 400);
  ASSERT_EQ(p.height, 300);
  expectTerrain(p);
}

TEST(AalView, TogglingVsyncMidFlightChangesThePresentMode) {
  TempDir dir;
  const fs::path shot = dir.path() / "shot.png";
  const auto r = view(dir, quoted(kDem) +
                               " --size 160x120 --frames 4 --toggle-vsync-after 2 --timeout 30"
                               " --screenshot " +
                               quoted(shot) + " --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("validation on, 0 messages"), std::string::npos) << r.out;
  // From FIFO to MAILBOX or IMMEDIATE (lavapipe's X11 surfaces offer both),
  // and frames drawn after the switch.
  EXPECT_NE(r.out.find("present mode fifo (vsync) -> "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("present    "), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("present    fifo"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames     4"), std::string::npos) << r.out;
  const Picture p = readPng(shot);
  ASSERT_EQ(p.width, 160);
  EXPECT_GT(greenSpread(p, 0, 120), 2.0);
}

TEST(AalView, MinimisingUnderXvfbLeavesTheWindowDrawing) {
  TempDir dir;
  const fs::path shot = dir.path() / "shot.png";
  const auto r = view(dir, quoted(kDem) +
                               " --size 160x120 --frames 10 --minimise-after 2 --timeout 30"
                               " --screenshot " +
                               quoted(shot) + " --stats");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  EXPECT_NE(r.out.find("validation on, 0 messages"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("minimising the window"), std::string::npos) << r.out;
  // Xvfb runs no window manager, and on X11 the window manager iconifies:
  // glfwIconifyWindow only asks it to, so the window stays as it was, the
  // viewer goes on drawing and restores it after a few event-loop
  // iterations. The minimised path itself (no frames until restored) cannot
  // be reached here.
  EXPECT_NE(r.out.find("restored the window: it was not minimised"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("frames     10"), std::string::npos) << r.out;
  const Picture p = readPng(shot);
  ASSERT_EQ(p.width, 160);
  ASSERT_EQ(p.height, 120);
  EXPECT_GT(greenSpread(p, 0, 120), 2.0);
}

// --horizons (aal-bake --horizons): the horizon mode, chosen at the start or
// switched to mid-flight as from the panel (a new pipeline variant; the
// slopes laid with the sun's horizons), renders without validation messages; under a low sun
// its picture is not approx's. Without horizons, or with another DEM's,
// exit 2 before a window opens.
TEST(AalView, HorizonModeWithTheBakesHorizonsAlsoSwitchedMidFlight) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr", horizons = dir.path() / "a.horizons";
  ASSERT_EQ(test::bakeWithHorizons(kDem, map, horizons), 0);
  const std::string common = quoted(kDem) + " --aperture " + quoted(map) +
                             " --sun-azimuth 250 --sun-elevation 12 --size 160x120 --frames 4"
                             " --timeout 60 --stats --screenshot ";
  const fs::path approxShot = dir.path() / "approx.png", horizonShot = dir.path() / "horizon.png",
                 switchedShot = dir.path() / "switched.png";
  const auto approx = view(dir, common + quoted(approxShot));
  ASSERT_EQ(approx.exitCode, 0) << approx.out;
  const auto horizon =
      view(dir, common + quoted(horizonShot) + " --mode horizon --horizons " + quoted(horizons));
  ASSERT_EQ(horizon.exitCode, 0) << horizon.out;  // 1 on any validation message
  EXPECT_NE(horizon.out.find("validation on, 0 messages"), std::string::npos) << horizon.out;
  const auto switched = view(dir, common + quoted(switchedShot) + " --mode-after 2:horizon" +
                                      " --horizons " + quoted(horizons));
  ASSERT_EQ(switched.exitCode, 0) << switched.out;
  EXPECT_NE(switched.out.find("validation on, 0 messages"), std::string::npos) << switched.out;
  EXPECT_NE(switched.out.find("frames     4"), std::string::npos) << switched.out;

  const Picture a = readPng(approxShot), h = readPng(horizonShot), s = readPng(switchedShot);
  ASSERT_EQ(h.width, 160);
  ASSERT_EQ(s.rgba.size(), h.rgba.size());
  ASSERT_EQ(a.rgba.size(), h.rgba.size());
  expectTerrain(h);
  int switchedWorst = 0;
  size_t differs = 0;  // green channels more than 2 LSB from approx's
  for (size_t i = 0; i < h.rgba.size(); ++i) {
    switchedWorst = std::max(switchedWorst, std::abs(int(s.rgba[i]) - int(h.rgba[i])));
    if (i % 4 == 1 && std::abs(int(h.rgba[i]) - int(a.rgba[i])) > 2) ++differs;
  }
  EXPECT_LE(switchedWorst, 1) << "the switched run ends on the horizon mode's picture";
  // The sun 12 degrees up: the horizons change some of the picture, 0.33 %
  // of its pixels (jacksboro's relief is gentle, and in this distant view
  // most fragments read prefiltered horizons, whose moments give the share
  // of a partly lit footprint that the sun clears, docs/rendering.md; 0.7 %
  // with the lower two of each 2 x 2 in the levels, 1-3 % with the mean
  // horizon alone). A horizon mode that drew approx's picture would change
  // none.
  std::printf("horizon against approx: %zu of %zu pixels differ by more than 2 LSB\n", differs,
              h.rgba.size() / 4);
  EXPECT_GT(differs, h.rgba.size() / 4 / 1000) << "the horizon mode looks like approx";

  // Without --aperture the viewer's own bake keeps the horizons (and caches
  // them beside the map): the mode is offered once baked, and again from the
  // cache, with the picture of aal-bake's default horizons (16 directions;
  // which differs from that of 8).
  const fs::path map16 = dir.path() / "a16.exr", horizons16 = dir.path() / "a16.horizons",
                 shot16 = dir.path() / "horizon16.png";
  ASSERT_EQ(test::bakeWithHorizons(kDem, map16, horizons16, 16), 0);
  const auto horizon16 =
      view(dir, common + quoted(shot16) + " --mode horizon --horizons " + quoted(horizons16));
  ASSERT_EQ(horizon16.exitCode, 0) << horizon16.out;
  const Picture h16 = readPng(shot16);
  ASSERT_EQ(h16.rgba.size(), h.rgba.size());
  const std::string own = quoted(kDem) +
                          " --sun-azimuth 250 --sun-elevation 12 --size 160x120 --frames 4"
                          " --timeout 120 --stats --mode-after 2:horizon --screenshot ";
  for (const char* run : {"baked.png", "cached.png"}) {
    const fs::path shot = dir.path() / run;
    const auto r = view(dir, own + quoted(shot));
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_NE(r.out.find("switched the shading mode"), std::string::npos) << run << r.out;
    const Picture p = readPng(shot);
    ASSERT_EQ(p.rgba.size(), h16.rgba.size());
    int worst = 0;
    for (size_t i = 0; i < h16.rgba.size(); ++i) {
      worst = std::max(worst, std::abs(int(p.rgba[i]) - int(h16.rgba[i])));
    }
    EXPECT_LE(worst, 1) << run;
  }
  EXPECT_EQ(filesIn(dir.path() / "cache"), 2u) << "the map and its horizons";

  const fs::path other = dir.path() / "other.tif", otherHorizons = dir.path() / "o.horizons";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(other) + " --size 32").exitCode, 0);
  ASSERT_EQ(runTool("aal-bake", quoted(other) + " -o " + quoted(dir.path() / "o.exr") +
                                    " --horizons " + quoted(otherHorizons) + " -q")
                .exitCode,
            0);
  const std::string dem = quoted(kDem) + " --frames 2 ";
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {dem + "--mode horizon", "--horizons FILE"},
           {dem + "--aperture " + quoted(map) + " --mode-after 1:horizon", "--horizons FILE"},
           {dem + "--mode-after 1:magic", "--mode-after"},
           {dem + "--horizons " + quoted(otherHorizons), "32x32, the DEM 403x344"},
           {dem + "--horizons " + quoted(other), "not a horizon map"},
           {dem + "--horizons " + quoted(dir.path() / "none.horizons"), "cannot open"}}) {
    const auto r = runTool("aal-view", args, "-u DISPLAY -u WAYLAND_DISPLAY");
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(message), std::string::npos) << args << "\n" << r.out;
  }
  const auto help = runTool("aal-view", "--help");
  EXPECT_NE(help.out.find("--horizons"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("--mode-after"), std::string::npos) << help.out;
}

// The horizon mode with a sun that moves past a stored direction mid-flight
// (--sun-azimuth-after, as the panel's direct sun): at 250 degrees the two
// stored directions beside the sun (8 of them) are 4 and 5 as laid at the
// start, at 292 they are 3 and 4, so the renderer re-lays the horizons
// between frames, under validation without a message; the last picture is
// that of a run started with the sun at 292 (laid for it from the start: no
// re-lay), within 1 LSB.
TEST(AalView, HorizonModeReLaysTheHorizonsWhenTheSunPassesADirection) {
  TempDir dir;
  const fs::path map = dir.path() / "a.exr", horizons = dir.path() / "a.horizons";
  ASSERT_EQ(test::bakeWithHorizons(kDem, map, horizons), 0);
  const std::string common = quoted(kDem) + " --aperture " + quoted(map) + " --horizons " +
                             quoted(horizons) +
                             " --mode horizon --sun-elevation 12 --size 160x120 --frames 4"
                             " --timeout 60 --stats --screenshot ";
  const fs::path movedShot = dir.path() / "moved.png", stillShot = dir.path() / "still.png";
  const auto moved =
      view(dir, common + quoted(movedShot) + " --sun-azimuth 250 --sun-azimuth-after 2:292");
  ASSERT_EQ(moved.exitCode, 0) << moved.out;  // 1 on any validation message
  EXPECT_NE(moved.out.find("validation on, 0 messages"), std::string::npos) << moved.out;
  EXPECT_NE(moved.out.find("moved the sun to azimuth 292 degrees"), std::string::npos) << moved.out;
  EXPECT_NE(moved.out.find("horizons   re-laid 1 times for the sun (directions 3 and 4 now)"),
            std::string::npos)
      << moved.out;
  EXPECT_NE(moved.out.find("frames     4"), std::string::npos) << moved.out;
  const auto still = view(dir, common + quoted(stillShot) + " --sun-azimuth 292");
  ASSERT_EQ(still.exitCode, 0) << still.out;
  EXPECT_NE(still.out.find("horizons   re-laid 0 times for the sun (directions 3 and 4 now)"),
            std::string::npos)
      << still.out;

  // And the picture the sun left: the move shows.
  const fs::path beforeShot = dir.path() / "before.png";
  ASSERT_EQ(view(dir, common + quoted(beforeShot) + " --sun-azimuth 250").exitCode, 0);

  const Picture m = readPng(movedShot), s = readPng(stillShot), b = readPng(beforeShot);
  ASSERT_EQ(m.width, 160);
  ASSERT_EQ(m.rgba.size(), s.rgba.size());
  ASSERT_EQ(m.rgba.size(), b.rgba.size());
  int worst = 0;
  size_t moves = 0;  // green channels more than 2 LSB from the picture at 250 degrees
  for (size_t i = 0; i < m.rgba.size(); ++i) {
    worst = std::max(worst, std::abs(int(m.rgba[i]) - int(s.rgba[i])));
    if (i % 4 == 1 && std::abs(int(m.rgba[i]) - int(b.rgba[i])) > 2) ++moves;
  }
  EXPECT_LE(worst, 1) << "the moved sun's picture against a run started there";
  EXPECT_GT(moves, m.rgba.size() / 4 / 10) << "the sun's move does not show";
}

// The aperture map as GeoTIFF (aal-bake -o map.tif) is taken as the EXR is:
// its floats become the halves the EXR holds, so the picture is the EXR's;
// the same check against the DEM: another DEM's map exits with 2.
TEST(AalView, TakesTheApertureMapAsGeoTiff) {
  TempDir dir;
  std::vector<Picture> shots;
  for (const char* name : {"a.exr", "a.tif"}) {
    const fs::path map = dir.path() / name, shot = dir.path() / (std::string(name) + ".png");
    const auto bake =
        runTool("aal-bake", quoted(kDem) + " -o " + quoted(map) + " --azimuths 16 -q");
    ASSERT_EQ(bake.exitCode, 0) << bake.out;
    const auto r = view(dir, quoted(kDem) + " --aperture " + quoted(map) +
                                 " --size 160x120 --frames 2 --timeout 60 --stats --screenshot " +
                                 quoted(shot));
    ASSERT_EQ(r.exitCode, 0) << r.out;
    EXPECT_NE(r.out.find("validation on, 0 messages"), std::string::npos) << r.out;
    shots.push_back(readPng(shot));
  }
  ASSERT_EQ(shots[0].width, 160);
  EXPECT_TRUE(shots[0].rgba == shots[1].rgba);
  const fs::path other = dir.path() / "other.tif";
  ASSERT_EQ(runTool("aal-synth", "-o " + quoted(other) + " --size 32").exitCode, 0);
  const auto refused =
      view(dir, quoted(other) + " --aperture " + quoted(dir.path() / "a.tif") + " --frames 1");
  EXPECT_EQ(refused.exitCode, 2) << refused.out;
  EXPECT_NE(refused.out.find("does not belong to DEM"), std::string::npos) << refused.out;
}

TEST(AalView, WindowHooksAreInTheHelpAndMalformedOnesExitWithTwo) {
  const std::string dem = quoted(kDem);
  for (const std::string& args :
       {dem + " --resize-after 2", dem + " --resize-after 2:0x10", dem + " --resize-after x:10x10",
        dem + " --resize-after 0:10x10", dem + " --frames 3 --resize-after 3:10x10",
        dem + " --minimise-after -1", dem + " --minimise-after 1:2",
        dem + " --toggle-vsync-after ''", dem + " --frames 2 --toggle-vsync-after 5",
        dem + " --sun-azimuth-after 2", dem + " --sun-azimuth-after 2:east",
        dem + " --sun-azimuth-after 2:800", dem + " --frames 2 --sun-azimuth-after 3:90"}) {
    const auto r = runTool("aal-view", args, "-u DISPLAY -u WAYLAND_DISPLAY");
    EXPECT_EQ(r.exitCode, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find("-after"), std::string::npos) << args << "\n" << r.out;
  }
  const auto help = runTool("aal-view", "--help");
  for (const char* text :
       {"--resize-after", "--minimise-after", "--toggle-vsync-after", "--sun-azimuth-after"}) {
    EXPECT_NE(help.out.find(text), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace aal
