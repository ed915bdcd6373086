#include "aperture/terrain/io/aperture_map.h"

#include <gtest/gtest.h>

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>

#include <filesystem>
#include <fstream>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/pixel_checksum.h"
#include "aperture/tests/preprocess/bake_test_util.h"
#include "aperture/tests/preprocess/map_test_util.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

Heightfield smallField(double bump = 0) {
  return test::makeField(20, 10, 25.0, [&](double x, double y) { return 0.01 * x * y + bump; });
}

TEST(ApertureMap, RoundTripsWithItsAttributes) {
  test::TempDir dir;
  const Heightfield field = smallField();
  BakeResult r = bakeApertures(field, BakeOptions{});
  r.aperture.info.source = "small.tif";
  const std::string path = (dir.path() / "a.exr").string();
  writeApertureMap(path, r.aperture, /*halfFloat=*/false);
  const ApertureMap back = readApertureMap(path);
  EXPECT_EQ(back.width, 20);
  EXPECT_EQ(back.height, 10);
  EXPECT_EQ(back.texels, r.aperture.texels);
  EXPECT_EQ(back.info.version, 1);
  EXPECT_EQ(back.info.azimuths, 64);
  EXPECT_EQ(back.info.method, "sweep");
  EXPECT_EQ(back.info.source, "small.tif");
  EXPECT_EQ(back.info.sourceWidth, 20);
  EXPECT_EQ(back.info.sourceHeight, 10);
  EXPECT_EQ(back.info.edge, "open");
  EXPECT_FLOAT_EQ(back.info.cellSizeX, 25.0f);
  EXPECT_EQ(back.info.sourceChecksum, heightfieldChecksum(field));
  EXPECT_NO_THROW(checkApertureMatchesDem(back, path, field, "small.tif"));
}

TEST(ApertureMap, HalfFloatKeepsThreeDigits) {
  test::TempDir dir;
  const BakeResult r = bakeApertures(smallField(), BakeOptions{});
  const std::string path = (dir.path() / "h.exr").string();
  writeApertureMap(path, r.aperture, /*halfFloat=*/true);
  const ApertureMap back = readApertureMap(path);
  for (size_t i = 0; i < back.texels.size(); ++i) {
    EXPECT_NEAR(back.texels[i], r.aperture.texels[i], 1e-3) << i;
  }
}

TEST(ApertureMap, StreamsRowsAsHalves) {
  test::TempDir dir;
  const Heightfield field = smallField();
  const BakeResult r = bakeApertures(field, BakeOptions{});
  const std::string path = (dir.path() / "s.exr").string();
  writeApertureMap(path, r.aperture, /*halfFloat=*/true);
  ApertureMapReader reader(path);
  EXPECT_EQ(reader.header().width, 20);
  EXPECT_EQ(reader.header().info.sourceChecksum, heightfieldChecksum(field));
  EXPECT_NO_THROW(checkApertureMatchesDem(reader.header(), path, field, "small.tif"));
  // Rows 3..7 in one band, compared with the whole map read as floats.
  const ApertureMap whole = readApertureMap(path);
  std::vector<uint16_t> halves(5 * 20 * 4);
  reader.readHalfRows(3, 8, halves.data());
  for (size_t i = 0; i < halves.size(); ++i) {
    const float expected = whole.texels[3 * 20 * 4 + i];
    Imath::half value;
    value.setBits(halves[i]);
    ASSERT_NEAR(float(value), expected, 1e-6) << i;
  }
}

TEST(ApertureMap, RefusesAMapOfAnotherDem) {
  const Heightfield field = smallField();
  const BakeResult r = bakeApertures(field, BakeOptions{});
  const Heightfield other = smallField(1.0);
  try {
    checkApertureMatchesDem(r.aperture, "a.exr", other, "other.tif");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a.exr"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("other.tif"), std::string::npos);
  }
  const Heightfield bigger = test::makeField(21, 10, 25.0, [](double, double) { return 0.0; });
  EXPECT_THROW(checkApertureMatchesDem(r.aperture, "a.exr", bigger, "b.tif"), InputError);
}

// Older maps carry the version 1 (byte-serial) heights checksum: still
// accepted with their DEM (the version 1 checksum is computed for them),
// refused with another.
TEST(ApertureMap, AMapWithTheOlderChecksumMatchesItsDemOnly) {
  test::TempDir dir;
  const Heightfield field = smallField();
  BakeResult r = bakeApertures(field, BakeOptions{});
  EXPECT_EQ(r.aperture.info.sourceChecksum, heightfieldChecksum(field));
  r.aperture.info.sourceChecksum = legacyHeightfieldChecksum(field);
  const std::string path = (dir.path() / "old.exr").string();
  writeApertureMap(path, r.aperture, /*halfFloat=*/true);
  ApertureMapReader reader(path);
  EXPECT_EQ(reader.header().info.sourceChecksum, legacyHeightfieldChecksum(field));
  EXPECT_NO_THROW(checkApertureMatchesDem(reader.header(), path, field, "small.tif"));
  EXPECT_THROW(checkApertureMatchesDem(reader.header(), path, smallField(1.0), "other.tif"),
               InputError);
}

TEST(ApertureMap, BadFilesGiveInputErrors) {
  test::TempDir dir;
  EXPECT_THROW(readApertureMap((dir.path() / "missing.exr").string()), InputError);
  // An EXR without aal: attributes.
  const std::string plain = (dir.path() / "plain.exr").string();
  {
    auto out = OIIO::ImageOutput::create(plain);
    OIIO::ImageSpec spec(4, 4, 4, OIIO::TypeDesc::FLOAT);
    std::vector<float> pixels(64, 0.5f);
    ASSERT_TRUE(out->open(plain, spec));
    ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
    out->close();
  }
  EXPECT_THROW(readApertureMap(plain), InputError);
  // A truncated aperture map.
  const std::string good = (dir.path() / "good.exr").string();
  writeApertureMap(good, bakeApertures(smallField(), BakeOptions{}).aperture, false);
  const auto size = std::filesystem::file_size(good);
  std::filesystem::resize_file(good, size / 2);
  EXPECT_THROW(readApertureMap(good), InputError);
  // Garbage.
  const std::string junk = (dir.path() / "junk.exr").string();
  std::ofstream(junk) << "not an image";
  EXPECT_THROW(readApertureMap(junk), InputError);
}

// Every map carries the checksum of its pixels as stored.
TEST(ApertureMap, CarriesTheChecksumOfItsPixels) {
  test::TempDir dir;
  const BakeResult r = bakeApertures(smallField(), BakeOptions{});
  for (const bool halfFloat : {true, false}) {
    const std::string path = (dir.path() / (halfFloat ? "h.exr" : "f.exr")).string();
    writeApertureMap(path, r.aperture, halfFloat);
    ApertureMapReader reader(path);
    ASSERT_TRUE(reader.header().pixelChecksum.has_value());
    PixelChecksum sum(10);
    const size_t rowFloats = 20 * 4;
    for (int row = 0; row < 10; ++row) {
      const float* floats = r.aperture.texels.data() + row * rowFloats;
      std::vector<Imath::half> halves(floats, floats + rowFloats);
      if (halfFloat) {
        sum.addRow(row, halves.data(), rowFloats * 2);
      } else {
        sum.addRow(row, floats, rowFloats * 4);
      }
    }
    EXPECT_EQ(*reader.header().pixelChecksum, sum.value()) << path;
    EXPECT_NO_THROW(reader.verify());
    EXPECT_NO_THROW(readApertureMap(path));
  }
}

// A map whose pixel data changed by one bit (uncompressed, so that it still
// decodes) is refused by every reader, naming the file and the checksum;
// each row band decodes, and the band that completes the rows throws.
TEST(ApertureMap, AFlippedPixelBitIsRefused) {
  test::TempDir dir;
  const BakeResult r = bakeApertures(smallField(), BakeOptions{});
  for (const bool halfFloat : {true, false}) {
    SCOPED_TRACE(halfFloat ? "halves" : "floats");
    const std::string path = (dir.path() / (halfFloat ? "h.exr" : "f.exr")).string();
    writeApertureMap(path, r.aperture, halfFloat, MapCompression::None);
    // The file ends with the last row's R channel: the second-last byte is
    // in the last texel's red value, its lowest bit a mantissa bit.
    test::flipByteFromEnd(path, 2);
    auto expectRefused = [&](auto&& read) {
      try {
        read();
        ADD_FAILURE() << "a map with a flipped bit was read";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("checksum"), std::string::npos) << e.what();
      }
    };
    expectRefused([&] { readApertureMap(path); });
    expectRefused([&] { ApertureMapReader(path).verify(); });
    ApertureMapReader reader(path);
    std::vector<uint16_t> halves(20 * 10 * 4);
    // Rows 8 and 9 (with the flipped bit) first: nothing to compare yet.
    EXPECT_NO_THROW(reader.readHalfRows(8, 10, halves.data()));
    EXPECT_NO_THROW(reader.readHalfRows(0, 5, halves.data()));
    expectRefused([&] { reader.readHalfRows(3, 8, halves.data()); });
  }
}

// Maps written before the checksum existed have none and read as before.
TEST(ApertureMap, AMapWithoutAChecksumIsRead) {
  test::TempDir dir;
  const BakeResult r = bakeApertures(smallField(), BakeOptions{});
  const std::string path = (dir.path() / "old.exr").string();
  writeApertureMap(path, r.aperture, /*halfFloat=*/false);
  test::removePixelChecksum(path);
  ApertureMapReader reader(path);
  EXPECT_FALSE(reader.header().pixelChecksum.has_value());
  EXPECT_NO_THROW(reader.verify());
  EXPECT_EQ(readApertureMap(path).texels, r.aperture.texels);
}

}  // namespace
}  // namespace aal
