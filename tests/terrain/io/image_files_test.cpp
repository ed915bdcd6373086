// The image plugin (terrain/io/image_files.h, oiio_image_plugin.cpp) does what
// the code that called OpenImageIO directly did, to the bit; it is found
// next to the executable or where AAL_IMAGE_PLUGIN says, and a plugin that
// does not load is an error naming it.
#include "aperture/terrain/io/image_files.h"

#include <gtest/gtest.h>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "aperture/terrain/io/image_plugin.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

constexpr const char* kFont = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

std::string fileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<float> randomValues(size_t count, float lowest, float highest) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> value(lowest, highest);
  std::vector<float> values(count);
  for (float& v : values) v = value(rng);
  return values;
}

std::vector<float> oiioPixels(const OIIO::ImageBuf& image) {
  std::vector<float> values(image.spec().image_pixels() * image.nchannels());
  EXPECT_TRUE(image.get_pixels(image.roi(), OIIO::TypeDesc::FLOAT, values.data()));
  return values;
}

TEST(ImageFiles, ReadsAsOpenImageIo) {
  test::TempDir dir;
  const std::string png = (dir.path() / "a.png").string();
  std::vector<uint8_t> bytes(5 * 3 * 4);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(i * 37);
  {
    auto out = OIIO::ImageOutput::create(png);
    ASSERT_TRUE(out->open(png, OIIO::ImageSpec(5, 3, 4, OIIO::TypeDesc::UINT8)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, bytes.data()));
    out->close();
  }
  const ImagePixels a = readImageFile(png);
  EXPECT_EQ(a.width, 5);
  EXPECT_EQ(a.height, 3);
  EXPECT_EQ(a.channels, 4);
  EXPECT_TRUE(a.integerSamples);
  OIIO::ImageBuf expected(png);
  ASSERT_TRUE(expected.read(0, 0, true, OIIO::TypeDesc::FLOAT));
  EXPECT_EQ(a.values, oiioPixels(expected));

  const std::string exr = (dir.path() / "a.exr").string();
  const std::vector<float> floats = randomValues(4 * 2 * 1, -1, 3);
  {
    auto out = OIIO::ImageOutput::create(exr);
    ASSERT_TRUE(out->open(exr, OIIO::ImageSpec(4, 2, 1, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, floats.data()));
    out->close();
  }
  const ImagePixels b = readImageFile(exr);
  EXPECT_EQ(b.channels, 1);
  EXPECT_FALSE(b.integerSamples);
  EXPECT_EQ(b.values, floats);
}

TEST(ImageFiles, ResizesAsOpenImageIo) {
  ImagePixels image;
  image.width = 13;
  image.height = 7;
  image.channels = 3;
  image.values = randomValues(13 * 7 * 3, 0, 1);
  OIIO::ImageBuf source(OIIO::ImageSpec(13, 7, 3, OIIO::TypeDesc::FLOAT), image.values.data());
  for (const auto& [width, height] : {std::pair{20, 11}, std::pair{5, 3}, std::pair{13, 30}}) {
    const ImagePixels resized = resizeImage(image, width, height);
    EXPECT_EQ(resized.width, width);
    EXPECT_EQ(resized.height, height);
    EXPECT_EQ(resized.channels, 3);
    const OIIO::ImageBuf expected = OIIO::ImageBufAlgo::resize(
        source, "triangle", 0.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, 3));
    EXPECT_EQ(resized.values, oiioPixels(expected)) << width << "x" << height;
  }
}

TEST(ImageFiles, WritesAsOpenImageIo) {
  test::TempDir dir;
  // Bytes: a PNG as ImageOutput writes samples whose colour is not
  // multiplied by their alpha (PNG's own convention; the renderer's frames,
  // whose supersampled silhouettes have alpha between 0 and 1). Without
  // "oiio:UnassociatedAlpha" it would divide the colour by alpha.
  std::vector<uint8_t> bytes(6 * 4 * 4);
  for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(i * 11);
  const auto ours = dir.path() / "ours.png", theirs = dir.path() / "theirs.png";
  writeImageFile(ours.string(), 6, 4, 4, bytes.data());
  {
    auto out = OIIO::ImageOutput::create(theirs.string());
    OIIO::ImageSpec spec(6, 4, 4, OIIO::TypeDesc::UINT8);
    spec.attribute("oiio:UnassociatedAlpha", 1);
    ASSERT_TRUE(out->open(theirs.string(), spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::UINT8, bytes.data()));
    out->close();
  }
  EXPECT_EQ(fileBytes(ours), fileBytes(theirs));
  {
    // Stored as given: read back unassociated, every sample is the same.
    OIIO::ImageSpec config;
    config.attribute("oiio:UnassociatedAlpha", 1);
    auto in = OIIO::ImageInput::open(ours.string(), &config);
    ASSERT_TRUE(in);
    std::vector<uint8_t> back(bytes.size());
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::UINT8, back.data()));
    EXPECT_EQ(back, bytes);
  }

  // Floats rounded to 8 bits: as ImageBuf::write did (tools/cap_error_plot.cpp).
  std::vector<float> floats = randomValues(6 * 4 * 3, -0.2f, 1.2f);
  const auto ours8 = dir.path() / "ours8.png", theirs8 = dir.path() / "theirs8.png";
  writeImageFile(ours8.string(), 6, 4, 3, floats.data(), /*eightBit=*/true);
  OIIO::ImageBuf buffer(OIIO::ImageSpec(6, 4, 3, OIIO::TypeDesc::FLOAT), floats.data());
  ASSERT_TRUE(buffer.write(theirs8.string(), OIIO::TypeDesc::UINT8));
  EXPECT_EQ(fileBytes(ours8), fileBytes(theirs8));

  // Floats as floats: the linear EXR.
  const auto exr = dir.path() / "linear.exr";
  writeImageFile(exr.string(), 6, 4, 3, floats.data(), /*eightBit=*/false);
  OIIO::ImageBuf back(exr.string());
  ASSERT_TRUE(back.read(0, 0, true, OIIO::TypeDesc::FLOAT));
  EXPECT_EQ(back.nativespec().format, OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(oiioPixels(back), floats);
}

TEST(ImageFiles, DrawsTextAsOpenImageIo) {
  ASSERT_TRUE(std::filesystem::exists(kFont)) << "install fonts-dejavu-core";
  std::vector<float> ours(120 * 40 * 3, 1.0f);
  std::vector<float> theirs = ours;
  for (const TextAlign align : {TextAlign::Left, TextAlign::Center, TextAlign::Right}) {
    drawText(ours.data(), 120, 40, 60, 28, "r1 = 45 deg", 14, kFont, {0.2f, 0.0f, 0.5f}, align);
    OIIO::ImageBuf image(OIIO::ImageSpec(120, 40, 3, OIIO::TypeDesc::FLOAT), theirs.data());
    const float colour[3] = {0.2f, 0.0f, 0.5f};
    const auto alignX = align == TextAlign::Left     ? OIIO::ImageBufAlgo::TextAlignX::Left
                        : align == TextAlign::Center ? OIIO::ImageBufAlgo::TextAlignX::Center
                                                     : OIIO::ImageBufAlgo::TextAlignX::Right;
    ASSERT_TRUE(
        OIIO::ImageBufAlgo::render_text(image, 60, 28, "r1 = 45 deg", 14, kFont, colour, alignX));
  }
  EXPECT_EQ(ours, theirs);
  EXPECT_NE(ours, std::vector<float>(ours.size(), 1.0f));
}

TEST(ImageFiles, FailuresAreImageFileErrors) {
  test::TempDir dir;
  EXPECT_THROW(readImageFile((dir.path() / "missing.png").string()), ImageFileError);
  const std::string junk = (dir.path() / "junk.png").string();
  std::ofstream(junk) << "not an image";
  EXPECT_THROW(readImageFile(junk), ImageFileError);
  const uint8_t pixel[4] = {1, 2, 3, 4};
  EXPECT_THROW(writeImageFile((dir.path() / "no-folder" / "a.png").string(), 1, 1, 4, pixel),
               ImageFileError);
  EXPECT_THROW(writeImageFile((dir.path() / "a.unknown-format").string(), 1, 1, 4, pixel),
               ImageFileError);
  std::vector<float> rgb(30 * 3);
  EXPECT_THROW(drawText(rgb.data(), 10, 3, 0, 2, "x", 12, (dir.path() / "no-font.ttf").string(),
                        {0, 0, 0}, TextAlign::Left),
               ImageFileError);
}

TEST(ImagePlugin, AMissingOrForeignPluginIsAnErrorNamingIt) {
  const std::string missing = "/nonexistent/aal_oiio_images.so";
  try {
    openImagePlugin(missing);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(missing), std::string::npos) << what;
    EXPECT_NE(what.find("No such file"), std::string::npos) << what;
    EXPECT_NE(what.find("AAL_IMAGE_PLUGIN"), std::string::npos) << what;
  }
  test::TempDir dir;
  const std::string text = (dir.path() / "text.so").string();
  std::ofstream(text) << "not a library";
  try {
    openImagePlugin(text);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
  // A library, but not ours (the C library is where every process has it).
  try {
    openImagePlugin("libc.so.6");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("not an image plugin"), std::string::npos) << e.what();
  }
}

TEST(ImagePlugin, FoundBesideOrInstalledUnlessTheEnvironmentSaysOtherwise) {
  const char* set = std::getenv("AAL_IMAGE_PLUGIN");
  ASSERT_TRUE(set) << "the tests run with AAL_IMAGE_PLUGIN (tests/CMakeLists.txt)";
  const std::string configured = set;
  EXPECT_EQ(imagePluginPath(), configured);
  EXPECT_EQ(openImagePlugin(configured).version, kImagePluginVersion);
  const std::vector<std::string> places = imagePluginCandidates();
  ASSERT_EQ(places.size(), 3u);
  const std::filesystem::path folder =
      std::filesystem::read_symlink("/proc/self/exe").parent_path();
  EXPECT_EQ(std::filesystem::path(places[0]).parent_path(), folder);
  // An installed tool in <prefix>/bin finds it in <prefix>/lib.../aperture.
  EXPECT_EQ(std::filesystem::path(places[1]).parent_path().filename(), "aperture");
  EXPECT_EQ(std::filesystem::path(places[1])
                .lexically_relative(folder.parent_path())
                .begin()
                ->string()
                .rfind("lib", 0),
            0u)
      << places[1];
  EXPECT_EQ(std::filesystem::path(places[2]).parent_path().filename(), "aperture");
  for (const std::string& place : places) {
    EXPECT_EQ(std::filesystem::path(place).filename(),
              std::filesystem::path(configured).filename());
  }
  unsetenv("AAL_IMAGE_PLUGIN");
  const std::string found = imagePluginPath();
  setenv("AAL_IMAGE_PLUGIN", configured.c_str(), 1);
  EXPECT_NE(std::find(places.begin(), places.end(), found), places.end()) << found;
}

}  // namespace
}  // namespace aal
