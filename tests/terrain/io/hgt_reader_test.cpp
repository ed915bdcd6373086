// SRTM .hgt input: sizes, byte order, voids, position from the file name.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <vector>

#include "dem_loader.h"
#include "dem_test_util.h"
#include "georeference.h"
#include "hgt_reader.h"

namespace aal {
namespace {

// Big-endian int16 samples, value(i) at texel i.
template <typename Value>
std::string hgtBytes(int side, Value value) {
  std::string bytes(static_cast<size_t>(side) * static_cast<size_t>(side) * 2, '\0');
  for (size_t i = 0; i < bytes.size() / 2; ++i) {
    const auto v = static_cast<uint16_t>(static_cast<int16_t>(value(i)));
    bytes[2 * i] = static_cast<char>(v >> 8);
    bytes[2 * i + 1] = static_cast<char>(v & 0xff);
  }
  return bytes;
}

int16_t sampleAt(size_t i) {
  return static_cast<int16_t>(static_cast<int>(i % 9973) - 400);
}

class HgtReader : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = (dir_.path() / name).string();
    test::writeBytes(path, bytes);
    return path;
  }
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

TEST_F(HgtReader, ThreeArcSecondTileRoundTrips) {
  const std::string path = write("N36W085.hgt", hgtBytes(1201, sampleAt));
  const Heightfield f = loadDem(path, warnings_.options());
  ASSERT_EQ(f.width, 1201);
  ASSERT_EQ(f.height, 1201);
  EXPECT_EQ(f.format, "SRTM HGT");
  for (size_t i : {size_t{0}, size_t{1}, size_t{1200}, size_t{1201}, f.texelCount() - 1}) {
    EXPECT_EQ(f.z[i], static_cast<float>(sampleAt(i))) << i;
  }
  EXPECT_EQ(f.voidCount, 0u);
  EXPECT_TRUE(warnings_.messages.empty());
}

TEST_F(HgtReader, NameIsTheCentreOfTheSouthWestSample) {
  const Heightfield f = loadDem(write("N36W085.hgt", hgtBytes(1201, sampleAt)));
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  EXPECT_EQ(f.geo.epsg, 4326);
  EXPECT_DOUBLE_EQ(f.geo.originX, -85.0);  // west column
  EXPECT_DOUBLE_EQ(f.geo.originY, 37.0);   // north row
  EXPECT_DOUBLE_EQ(f.geo.stepX, 1.0 / 1200.0);
  // South-west sample (row 1200, column 0) at exactly 36 N, 85 W.
  EXPECT_NEAR(f.geo.originY - 1200 * f.geo.stepY, 36.0, 1e-12);
  EXPECT_NEAR(f.geo.centerLatDeg, 36.5, 1e-12);
  EXPECT_NEAR(f.geo.centerLonDeg, -84.5, 1e-12);
  // Metric spacing: 3" of longitude at the row's latitude, 3" of latitude.
  EXPECT_NEAR(f.rowCellSizeXM[1200], parallelArcM(36.0, 1.0 / 1200.0), 1e-9);
  EXPECT_NEAR(f.rowCellSizeXM[0], parallelArcM(37.0, 1.0 / 1200.0), 1e-9);
  EXPECT_NEAR(f.cellSizeYM, meridianArcM(36.0, 37.0) / 1200.0, 1e-9);
}

TEST_F(HgtReader, OneArcSecondTileSouthernAndEasternHemispheres) {
  const Heightfield f = loadDem(write("s12e130.SRTMGL1.hgt", hgtBytes(3601, sampleAt)));
  ASSERT_EQ(f.width, 3601);
  EXPECT_EQ(f.z[3601 * 3601 - 1], static_cast<float>(sampleAt(3601 * 3601 - 1)));
  EXPECT_DOUBLE_EQ(f.geo.originX, 130.0);
  EXPECT_DOUBLE_EQ(f.geo.originY, -11.0);
  EXPECT_DOUBLE_EQ(f.geo.stepY, 1.0 / 3600.0);
  EXPECT_NEAR(f.geo.centerLatDeg, -11.5, 1e-12);
  EXPECT_NEAR(f.cellSizeYM, 30.7, 0.1);  // 1" of latitude
}

TEST_F(HgtReader, VoidSamplesAreMaskedAndFilled) {
  const auto value = [](size_t i) { return i % 1201 < 3 && i / 1201 < 2 ? kHgtVoid : 250; };
  const Heightfield f = loadDem(write("N00E000.hgt", hgtBytes(1201, value)));
  EXPECT_EQ(f.voidCount, 6u);
  EXPECT_TRUE(f.isVoid(0, 0));
  EXPECT_TRUE(f.isVoid(2, 1));
  EXPECT_FALSE(f.isVoid(3, 1));
  EXPECT_EQ(f.at(0, 0), 250.0f);
  EXPECT_TRUE(test::allFinite(f));
}

TEST_F(HgtReader, AllVoidTileIsRefused) {
  const std::string path = write("N10E010.hgt", hgtBytes(1201, [](size_t) { return kHgtVoid; }));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }), {path, "every texel is void"});
}

TEST_F(HgtReader, WrongSizeIsRefused) {
  const std::string path = write("N36W085.hgt", hgtBytes(1200, sampleAt));
  test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                      {path, "2880000 bytes", "2884802 (1201 x 1201", "25934402 (3601 x 3601"});
  const std::string cut = write("N36W084.hgt", hgtBytes(1201, sampleAt).substr(0, 2884801));
  test::expectMessage(test::inputErrorOf([&] { loadDem(cut); }), {cut, "2884801 bytes"});
}

TEST_F(HgtReader, NameWithoutPositionGivesAnUngeoreferencedDemAndAWarning) {
  const Heightfield f = loadDem(write("tile.hgt", hgtBytes(1201, sampleAt)), warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::None);
  EXPECT_TRUE(warnings_.any("does not give the tile position"));
  EXPECT_TRUE(warnings_.any("--cell-size"));
}

TEST_F(HgtReader, ImpossibleTileNameIsRefused) {
  for (const char* name : {"N90E000.hgt", "S91E000.hgt", "N00E180.hgt", "N00W181.hgt"}) {
    const std::string path = write(name, hgtBytes(1201, sampleAt));
    test::expectMessage(test::inputErrorOf([&] { loadDem(path); }),
                        {path, "inconsistent georeferencing", "names no SRTM tile"});
  }
}

TEST(HgtTileName, ParsesHemispheresAndIgnoresFoldersAndCase) {
  const auto tile = parseHgtTileName("/data/n45e010.hgt");
  ASSERT_TRUE(tile);
  EXPECT_EQ(tile->southLatDeg, 45);
  EXPECT_EQ(tile->westLonDeg, 10);
  const auto south = parseHgtTileName("S90W180.hgt");
  ASSERT_TRUE(south);
  EXPECT_EQ(south->southLatDeg, -90);
  EXPECT_EQ(south->westLonDeg, -180);
  EXPECT_FALSE(parseHgtTileName("N4E010.hgt"));
  EXPECT_FALSE(parseHgtTileName("X45E010.hgt"));
  EXPECT_FALSE(parseHgtTileName("a.hgt"));
}

}  // namespace
}  // namespace aal
