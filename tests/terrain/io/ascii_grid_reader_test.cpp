// ESRI ASCII grid input: header variants, voids, .prj sidecar and bad text.
#include <gtest/gtest.h>

#include <string>

#include "ascii_grid_reader.h"
#include "dem_loader.h"
#include "dem_test_util.h"
#include "georeference.h"

namespace aal {
namespace {

class AsciiGridReader : public ::testing::Test {
 protected:
  std::string write(const std::string& text, const std::string& name = "dem.asc") {
    const std::string path = (dir_.path() / name).string();
    test::writeBytes(path, text);
    return path;
  }
  std::string errorOf(const std::string& text) {
    const std::string path = write(text);
    const std::string message = test::inputErrorOf([&] { loadDem(path, warnings_.options()); });
    EXPECT_NE(message.find(path), std::string::npos) << message;
    return message;
  }
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

constexpr const char* kGrid =
    "ncols 4\n"
    "nrows 3\n"
    "xllcorner 1000\n"
    "yllcorner 2000\n"
    "cellsize 10\n"
    "NODATA_value -9999\n"
    "1 2 3 4\n"
    "5 -9999 7.5 8\n"
    "9 10 11 -12.25\n";

TEST_F(AsciiGridReader, SamplesAndCornerGeoreferencingRoundTrip) {
  const Heightfield f = loadDem(write(kGrid), warnings_.options());
  ASSERT_EQ(f.width, 4);
  ASSERT_EQ(f.height, 3);
  EXPECT_EQ(f.format, "ESRI ASCII grid");
  EXPECT_EQ(f.at(0, 0), 1.0f);  // first row is north
  EXPECT_EQ(f.at(2, 1), 7.5f);
  EXPECT_EQ(f.at(3, 2), -12.25f);
  EXPECT_EQ(f.voidCount, 1u);
  EXPECT_TRUE(f.isVoid(1, 1));
  EXPECT_TRUE(test::allFinite(f));
  EXPECT_EQ(f.geo.crs, CrsKind::Projected);
  EXPECT_DOUBLE_EQ(f.geo.originX, 1005.0);  // centre of the west column
  EXPECT_DOUBLE_EQ(f.geo.originY, 2025.0);  // centre of the north row
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 10.0);
  EXPECT_TRUE(warnings_.messages.empty());
}

TEST_F(AsciiGridReader, CentreKeysAnyCaseAndOrderAndDxDy) {
  const Heightfield f =
      loadDem(write("NROWS 2\nNCOLS 2\nXLLCENTER 5\nyllCenter 7\n"
                    "dx 2\ndy 3\n1 2\n3 4\n"));
  EXPECT_DOUBLE_EQ(f.geo.originX, 5.0);
  EXPECT_DOUBLE_EQ(f.geo.originY, 10.0);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 2.0);
  EXPECT_DOUBLE_EQ(f.cellSizeYM, 3.0);
  EXPECT_EQ(f.at(1, 1), 4.0f);
}

TEST_F(AsciiGridReader, NanAndInfSamplesAreVoids) {
  const Heightfield f =
      loadDem(write("ncols 3\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                    "nan 4 -inf\n"));
  EXPECT_EQ(f.voidCount, 2u);
  EXPECT_EQ(f.at(0, 0), 4.0f);
  EXPECT_EQ(f.at(2, 0), 4.0f);
}

TEST_F(AsciiGridReader, GeographicPrjGivesMetricSpacing) {
  write(
      "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
      "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433],AUTHORITY[\"EPSG\",\"4326\"]]",
      "geo.prj");
  const std::string path = write(
      "ncols 3\nnrows 3\nxllcorner -85\nyllcorner 36\n"
      "cellsize 0.000833333333333\n1 2 3\n4 5 6\n7 8 9\n",
      "geo.asc");
  const Heightfield f = loadDem(path, warnings_.options());
  EXPECT_EQ(f.geo.crs, CrsKind::Geographic);
  EXPECT_EQ(f.geo.epsg, 4326);
  EXPECT_NEAR(f.cellSizeYM, 92.4, 0.2);
  EXPECT_NEAR(f.cellSizeXM, parallelArcM(f.geo.centerLatDeg, 0.000833333333333), 1e-9);
  EXPECT_TRUE(warnings_.messages.empty());
}

TEST_F(AsciiGridReader, ProjectedPrjInFeetScalesCells) {
  write(
      "PROJCS[\"NAD83 / Tennessee (ftUS)\",GEOGCS[\"NAD83\",UNIT[\"degree\",0.0174532925199433]],"
      "PROJECTION[\"Lambert_Conformal_Conic_2SP\"],UNIT[\"US survey foot\",0.304800609601219],"
      "AUTHORITY[\"EPSG\",\"2274\"]]",
      "ft.prj");
  const std::string path =
      write("ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 100\n1 2\n3 4\n", "ft.asc");
  const Heightfield f = loadDem(path);
  EXPECT_EQ(f.geo.epsg, 2274);
  EXPECT_NEAR(f.cellSizeXM, 30.4800609601219, 1e-9);
}

TEST_F(AsciiGridReader, DegreeSizedCellsWithoutPrjWarn) {
  loadDem(write("ncols 2\nnrows 2\nxllcorner -85\nyllcorner 36\ncellsize 0.001\n1 2\n3 4\n"),
          warnings_.options());
  EXPECT_TRUE(warnings_.any("looks like degrees"));
}

TEST_F(AsciiGridReader, NonNumericSampleNamesRowAndColumn) {
  test::expectMessage(errorOf("ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                              "1 2 3\n4 x5 6\n"),
                      {"non-numeric sample 'x5' at row 2, column 2"});
}

TEST_F(AsciiGridReader, TooFewSamplesAreTruncation) {
  test::expectMessage(errorOf("ncols 3\nnrows 3\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                              "1 2 3\n4 5 6\n7 8      \n"),
                      {"truncated: 8 samples of 9", "row 3 is incomplete"});
  // Far too few bytes: refused before allocating.
  test::expectMessage(errorOf("ncols 30000\nnrows 30000\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                              "1 2 3\n"),
                      {"truncated", "cannot hold 30000 x 30000 samples"});
}

TEST_F(AsciiGridReader, TooManySamplesAreRefused) {
  test::expectMessage(errorOf("ncols 2\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                              "1 2 3\n"),
                      {"more samples than ncols x nrows = 2", "'3'"});
}

TEST_F(AsciiGridReader, HeaderProblemsAreRefused) {
  const std::string rest = "xllcorner 0\nyllcorner 0\ncellsize 1\n1\n";
  test::expectMessage(errorOf("nrows 1\n" + rest), {"header lacks 'ncols'"});
  test::expectMessage(errorOf("ncols 1\nnrows 1\ncellsize 1\n1\n"),
                      {"header lacks 'xllcorner' or 'xllcenter'"});
  test::expectMessage(errorOf("ncols 1\nncols 1\nnrows 1\n" + rest), {"'ncols' appears twice"});
  test::expectMessage(errorOf("ncols one\nnrows 1\n" + rest),
                      {"'ncols' has non-numeric value 'one' on line 1"});
  test::expectMessage(errorOf("ncols 1.5\nnrows 1\n" + rest), {"'ncols' must be a whole number"});
  test::expectMessage(errorOf("ncols 1\nnrows 1\nbyteorder lsbfirst\n" + rest),
                      {"unknown header entry 'byteorder' on line 3"});
  test::expectMessage(errorOf("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize -2\n1\n"),
                      {"inconsistent georeferencing", "cell size must be positive"});
  test::expectMessage(
      errorOf("ncols 1\nnrows 1\nxllcorner 0\nxllcenter 0\nyllcorner 0\ncellsize 1\n1\n"),
      {"both 'xllcorner' and 'xllcenter'"});
}

TEST_F(AsciiGridReader, ZeroAndHugeSizesAreRefused) {
  const std::string rest = "xllcorner 0\nyllcorner 0\ncellsize 1\n1\n";
  test::expectMessage(errorOf("ncols 0\nnrows 1\n" + rest), {"size 0 x 1 has no texels"});
  test::expectMessage(errorOf("ncols -4\nnrows 1\n" + rest), {"has no texels"});
  test::expectMessage(errorOf("ncols 100000\nnrows 1\n" + rest),
                      {"limit of 65536 texels per side"});
}

TEST_F(AsciiGridReader, ParsesFromMemory) {
  const RawDem raw = parseAsciiGrid("mem.asc", kGrid, std::nullopt, DemLoadOptions{});
  EXPECT_EQ(raw.width, 4);
  EXPECT_EQ(raw.voidMask[5], 1);
  EXPECT_EQ(raw.z[11], -12.25f);
}

}  // namespace
}  // namespace aal
