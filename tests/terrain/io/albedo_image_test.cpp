// Albedo images (terrain/io/albedo_image): decoding, channels, resampling, errors.
#include "aperture/terrain/io/albedo_image.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "aperture/terrain/errors.h"
#include "aperture/tests/terrain/io/hostile_files.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

template <typename T>
void writeImage(const std::string& path, int width, int height, int channels, OIIO::TypeDesc type,
                const std::vector<T>& pixels) {
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out) << OIIO::geterror();
  ASSERT_TRUE(out->open(path, OIIO::ImageSpec(width, height, channels, type))) << out->geterror();
  ASSERT_TRUE(out->write_image(OIIO::BaseTypeFromC<T>::value, pixels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

// IEC 61966-2-1.
double srgbToLinear(double v) {
  return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
}

TEST(AlbedoImage, EightAndSixteenBitImagesAreLinearizedFromSrgb) {
  test::TempDir dir;
  const std::string png8 = (dir.path() / "a8.png").string();
  writeImage<uint8_t>(png8, 2, 1, 3, OIIO::TypeDesc::UINT8, {128, 64, 255, 0, 10, 200});
  const AlbedoImage a = loadAlbedoImage(png8, 2, 1, nullptr);
  ASSERT_EQ(a.rgb.size(), 6u);
  const uint8_t bytes[6] = {128, 64, 255, 0, 10, 200};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(a.rgb[i], srgbToLinear(bytes[i] / 255.0), 1e-6) << i;

  const std::string png16 = (dir.path() / "a16.png").string();
  writeImage<uint16_t>(png16, 1, 1, 3, OIIO::TypeDesc::UINT16, {32768, 1000, 65535});
  const AlbedoImage b = loadAlbedoImage(png16, 1, 1, nullptr);
  EXPECT_NEAR(b.rgb[0], srgbToLinear(32768 / 65535.0), 1e-6);
  EXPECT_NEAR(b.rgb[1], srgbToLinear(1000 / 65535.0), 1e-6);
  EXPECT_NEAR(b.rgb[2], 1.0, 1e-6);
}

TEST(AlbedoImage, FloatImagesAreLinearAndClamped) {
  test::TempDir dir;
  const std::string exr = (dir.path() / "a.exr").string();
  writeImage<float>(exr, 2, 1, 3, OIIO::TypeDesc::HALF, {0.25f, 0.5f, 1.5f, -0.5f, 0.125f, 1.0f});
  const AlbedoImage a = loadAlbedoImage(exr, 2, 1, nullptr);
  const std::vector<float> expected = {0.25f, 0.5f, 1.0f, 0.0f, 0.125f, 1.0f};
  EXPECT_EQ(a.rgb, expected);
}

TEST(AlbedoImage, GreyIsReplicatedAndAlphaIgnored) {
  test::TempDir dir;
  const std::string grey = (dir.path() / "grey.exr").string();
  writeImage<float>(grey, 1, 1, 1, OIIO::TypeDesc::FLOAT, {0.3f});
  EXPECT_EQ(loadAlbedoImage(grey, 1, 1, nullptr).rgb, (std::vector<float>{0.3f, 0.3f, 0.3f}));
  const std::string rgba = (dir.path() / "rgba.exr").string();
  writeImage<float>(rgba, 1, 1, 4, OIIO::TypeDesc::FLOAT, {0.1f, 0.2f, 0.4f, 0.0f});
  EXPECT_EQ(loadAlbedoImage(rgba, 1, 1, nullptr).rgb, (std::vector<float>{0.1f, 0.2f, 0.4f}));
}

// Triangle (bilinear) filter: a 2 x 1 step doubled in width; texel centres
// at 0.25 and 0.75 of the source texels blend 3:1 towards the nearer one
// (the ends clamp to the edge).
TEST(AlbedoImage, AnotherSizeIsResampledWithANote) {
  test::TempDir dir;
  const std::string exr = (dir.path() / "step.exr").string();
  writeImage<float>(exr, 2, 1, 1, OIIO::TypeDesc::FLOAT, {0.2f, 0.6f});
  std::string note;
  const AlbedoImage a = loadAlbedoImage(exr, 4, 1, [&](const std::string& m) { note = m; });
  EXPECT_NE(note.find("step.exr is 2x1, the DEM 4x1: resampled"), std::string::npos) << note;
  ASSERT_EQ(a.rgb.size(), 12u);
  const float expected[4] = {0.2f, 0.3f, 0.5f, 0.6f};
  for (int x = 0; x < 4; ++x) EXPECT_NEAR(a.rgb[3 * x], expected[x], 1e-6) << x;
}

TEST(AlbedoImage, BadFilesAreInputErrorsNamingThem) {
  test::TempDir dir;
  for (const std::string& path :
       {(dir.path() / "missing.png").string(), (dir.path() / "junk.png").string()}) {
    if (path.find("junk") != std::string::npos) std::ofstream(path) << "not an image";
    try {
      loadAlbedoImage(path, 4, 4, nullptr);
      FAIL() << "no error for " << path;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

// What an image's header claims is checked before a pixel is decoded: a
// PNG of a few bytes claiming 20000 x 20000 pixels is refused by what its
// bytes can hold at zlib's best ratio; any image beyond the memory
// available (AAL_MEMORY_LIMIT here) with both numbers; a FIFO or a folder
// for what it is, unopened.
TEST(AlbedoImage, HeadersClaimingMoreThanFitsAreRefusedBeforeDecoding) {
  test::TempDir dir;
  for (const auto& [name, bytes] : {std::pair{"grey.png", test::pngClaiming(20000, 20000)},
                                    std::pair{"rgb.png", test::rgbPngClaiming(20000, 20000)}}) {
    const std::string path = (dir.path() / name).string();
    std::ofstream(path, std::ios::binary) << bytes;
    try {
      loadAlbedoImage(path, 4, 4, nullptr);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("albedo image " + path +
                          " is truncated or corrupt: its header declares "
                          "20000 x 20000 pixels"),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("zlib's best ratio"), std::string::npos) << what;
    }
  }

  // A whole image, 600 x 400 RGB, beyond a limit of 4 MB.
  const std::string real = (dir.path() / "real.png").string();
  writeImage<uint8_t>(real, 600, 400, 3, OIIO::TypeDesc::UINT8,
                      std::vector<uint8_t>(600 * 400 * 3, 90));
  ASSERT_EQ(::setenv("AAL_MEMORY_LIMIT", "4M", 1), 0);
  try {
    loadAlbedoImage(real, 4, 4, nullptr);
    ADD_FAILURE() << "read within 4 MB";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("albedo image " + real + ": holding its 600 x 400 pixels of 3 channels"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("needs 5.8 MB, but only 4.2 MB of memory is available"), std::string::npos)
        << what;
  }
  ASSERT_EQ(::unsetenv("AAL_MEMORY_LIMIT"), 0);
  EXPECT_EQ(loadAlbedoImage(real, 4, 4, nullptr).rgb.size(), 48u);

  const std::string fifo = (dir.path() / "fifo.png").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  ::alarm(10);  // a read that blocks ends the test
  for (const auto& [path, says] :
       {std::pair{fifo, " is a FIFO, not a file"},
        std::pair{dir.path().string(), " is a folder, not an image file"}}) {
    try {
      loadAlbedoImage(path, 4, 4, nullptr);
      ADD_FAILURE() << path << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("albedo image " + path + says), std::string::npos)
          << e.what();
    }
  }
  ::alarm(0);
}

}  // namespace
}  // namespace aal
