// Plain images as DEMs (PNG 8/16-bit, OpenEXR, TIFF without GeoKeys):
// heights unscaled, no georeferencing, defaults with a warning, overrides.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <vector>

#include "dem_loader.h"
#include "dem_test_util.h"
#include "test_tiff.h"

namespace aal {
namespace {

class ImageFormats : public ::testing::Test {
 protected:
  template <typename T>
  std::string writeImage(const std::string& name, int channels, OIIO::TypeDesc type,
                         const std::vector<T>& pixels, OIIO::TypeDesc fileType = {}) {
    const std::string path = (dir_.path() / name).string();
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
    EXPECT_TRUE(out);
    const OIIO::ImageSpec spec(kWidth, kHeight, channels,
                               fileType == OIIO::TypeDesc() ? type : fileType);
    EXPECT_TRUE(out->open(path, spec)) << out->geterror();
    EXPECT_TRUE(out->write_image(type, pixels.data())) << out->geterror();
    out->close();
    return path;
  }
  static constexpr int kWidth = 6, kHeight = 5;
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

TEST_F(ImageFormats, Png16KeepsRawValues) {
  std::vector<uint16_t> pixels(kWidth * kHeight);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint16_t>(i * 2111 + 7);
  const Heightfield f =
      loadDem(writeImage("dem.png", 1, OIIO::TypeDesc::UINT16, pixels), warnings_.options());
  EXPECT_EQ(f.format, "PNG");
  ASSERT_EQ(f.width, kWidth);
  for (size_t i = 0; i < pixels.size(); ++i) EXPECT_EQ(f.z[i], static_cast<float>(pixels[i]));
  EXPECT_EQ(f.geo.crs, CrsKind::None);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, kDefaultCellSizeM);
  EXPECT_DOUBLE_EQ(f.zScale, kDefaultZScale);
  EXPECT_TRUE(warnings_.any("not georeferenced"));
  EXPECT_TRUE(warnings_.any("--cell-size"));
  EXPECT_TRUE(warnings_.any("--z-scale"));
}

TEST_F(ImageFormats, Png8WithOverridesHasNoWarning) {
  std::vector<uint8_t> pixels(kWidth * kHeight);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>(i * 8);
  DemLoadOptions o = warnings_.options();
  o.cellSizeM = 2.5;
  o.zScale = 0.5;
  const Heightfield f = loadDem(writeImage("dem.png", 1, OIIO::TypeDesc::UINT8, pixels), o);
  EXPECT_EQ(f.z[29], 29 * 8 * 0.5f);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 2.5);
  EXPECT_DOUBLE_EQ(f.cellSizeYM, 2.5);
  EXPECT_DOUBLE_EQ(f.zScale, 0.5);
  EXPECT_TRUE(warnings_.messages.empty()) << ::testing::PrintToString(warnings_.messages);
}

TEST_F(ImageFormats, RgbPngUsesTheFirstChannelAndWarns) {
  std::vector<uint8_t> pixels(kWidth * kHeight * 3);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>(i);
  const Heightfield f =
      loadDem(writeImage("rgb.png", 3, OIIO::TypeDesc::UINT8, pixels), warnings_.options());
  EXPECT_EQ(f.z[1], 3.0f);
  EXPECT_TRUE(warnings_.any("3 channels (R, G, B); using the first one (R)"));
}

TEST_F(ImageFormats, ExrSingleChannelFloatRoundTrips) {
  std::vector<float> pixels(kWidth * kHeight);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = -1234.5f + 97.25f * static_cast<float>(i);
  pixels[4] = std::numeric_limits<float>::quiet_NaN();
  const Heightfield f =
      loadDem(writeImage("dem.exr", 1, OIIO::TypeDesc::FLOAT, pixels), warnings_.options());
  EXPECT_EQ(f.format, "OpenEXR");
  EXPECT_EQ(f.z[7], pixels[7]);
  EXPECT_EQ(f.voidCount, 1u);
  EXPECT_TRUE(f.isVoid(4, 0));
  EXPECT_TRUE(test::allFinite(f));
}

TEST_F(ImageFormats, ExrHalfRgbaUsesTheFirstChannelAndWarns) {
  std::vector<float> pixels(kWidth * kHeight * 4);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(i % 512);
  const std::string path =
      writeImage("rgba.exr", 4, OIIO::TypeDesc::FLOAT, pixels, OIIO::TypeDesc::HALF);
  const Heightfield f = loadDem(path, warnings_.options());
  EXPECT_EQ(f.z[2], 8.0f);  // R of pixel 2: exact in half precision
  EXPECT_TRUE(warnings_.any("4 channels"));
}

TEST_F(ImageFormats, TiffWithoutGeoKeysIsAPlainImage) {
  test::TestTiff t;
  t.kind = test::SampleKind::UInt16;
  t.values = test::rampValues(t.width, t.height);
  for (double& v : t.values) v += 1000;
  const std::string path = (dir_.path() / "plain.tif").string();
  test::writeTestTiff(path, t);
  const Heightfield f = loadDem(path, warnings_.options());
  EXPECT_EQ(f.format, "TIFF");
  EXPECT_EQ(f.z[3], static_cast<float>(t.values[3]));
  EXPECT_EQ(f.geo.crs, CrsKind::None);
  EXPECT_FALSE(f.geo.hasCenter);
  EXPECT_TRUE(warnings_.any("not georeferenced"));
}

TEST_F(ImageFormats, TruncatedPngIsRefused) {
  std::vector<uint16_t> pixels(kWidth * kHeight, 500);
  const std::string path = writeImage("cut.png", 1, OIIO::TypeDesc::UINT16, pixels);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  test::writeBytes(path, bytes.substr(0, bytes.size() / 2));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "corrupt or truncated PNG", "runs past the end of the file"});
  test::writeBytes(path, bytes.substr(0, bytes.size() - 12));  // IEND missing
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "ends before the IEND chunk"});
}

TEST_F(ImageFormats, PngWithCorruptPixelDataIsRefused) {
  std::vector<uint16_t> pixels(kWidth * kHeight);
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint16_t>(i * 977);
  const std::string path = writeImage("bad.png", 1, OIIO::TypeDesc::UINT16, pixels);
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), {});
  const size_t idat = bytes.find("IDAT");
  ASSERT_NE(idat, std::string::npos);
  for (size_t i = idat + 6; i < idat + 20; ++i) bytes[i] = static_cast<char>(0xA5 ^ i);
  test::writeBytes(path, bytes);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "cannot decode rows", "(truncated or corrupt?)"});
}

TEST_F(ImageFormats, PngWithHugeHeaderSizeIsRefusedBeforeOpening) {
  std::string png("\x89PNG\r\n\x1a\n", 8);
  png += std::string("\0\0\0\x0dIHDR", 8) + std::string("\x00\x01\x86\xa0\x00\x00\x00\x02", 8) +
         std::string("\x08\x00\x00\x00\x00", 5) + std::string(4, '\0');  // 100000 x 2
  png += std::string("\0\0\0\0IEND", 8) + std::string(4, '\0');
  const std::string path = (dir_.path() / "huge.png").string();
  test::writeBytes(path, png);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {path, "100000 x 2", "limit of 65536 texels per side"});
}

TEST_F(ImageFormats, TruncatedExrIsRefused) {
  std::vector<float> pixels(64 * 64);
  for (size_t i = 0; i < pixels.size(); ++i)
    pixels[i] = std::sin(0.37f * static_cast<float>(i)) * 1e3f;
  const std::string path = (dir_.path() / "cut.exr").string();
  {
    std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path);
    ASSERT_TRUE(out->open(path, OIIO::ImageSpec(64, 64, 1, OIIO::TypeDesc::FLOAT)));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  }
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  test::writeBytes(path, bytes.substr(0, bytes.size() * 2 / 3));  // the header survives
  test::expectMessage(test::inputErrorOf([&] { loadDem(path, warnings_.options()); }),
                      {path, "cannot decode rows 0..63 (truncated or corrupt?)"});
}

// A hand-made OpenEXR header: magic, version word, attributes, end byte.
std::string exrHeader(uint32_t version, const std::string& attributes) {
  std::string bytes("\x76\x2f\x31\x01", 4);
  for (int i = 0; i < 4; ++i) bytes += static_cast<char>(version >> (8 * i));
  return bytes + attributes + std::string(1, '\0');
}

std::string int32s(std::initializer_list<int32_t> values) {
  std::string bytes;
  for (int32_t v : values) {
    for (int i = 0; i < 4; ++i) bytes += static_cast<char>(static_cast<uint32_t>(v) >> (8 * i));
  }
  return bytes;
}

std::string attribute(const std::string& name, const std::string& type, const std::string& value,
                      int32_t declaredSize) {
  return name + '\0' + type + '\0' + int32s({declaredSize}) + value;
}

TEST_F(ImageFormats, ExrWithHugeDataWindowIsRefusedBeforeOpenExrAllocates) {
  const std::string path = (dir_.path() / "huge.exr").string();
  test::writeBytes(path,
                   exrHeader(2, attribute("dataWindow", "box2i", int32s({0, 0, 99999, 9}), 16)));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {path, "100000 x 10", "limit of 65536 texels per side"});
}

TEST_F(ImageFormats, CorruptExrHeadersAreRefused) {
  const std::string path = (dir_.path() / "bad.exr").string();
  test::writeBytes(path, exrHeader(2, attribute("comments", "string", "hi", 1 << 30)));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {path, "corrupt OpenEXR header", "runs past the end of the file"});
  test::writeBytes(path, exrHeader(2, attribute("owner", "string", "me", 2)));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }), {"no dataWindow"});
  test::writeBytes(path, exrHeader(2, std::string(40, 'n')));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {"a name longer than 31 characters"});
  test::writeBytes(
      path, exrHeader(2 | 0x800, attribute("dataWindow", "box2i", int32s({0, 0, 3, 3}), 16)));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }), {"deep (non-image)"});
}

}  // namespace
}  // namespace aal
