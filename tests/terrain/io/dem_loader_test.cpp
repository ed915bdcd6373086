// loadDem as a whole: format detection, file-level errors, overrides, limits.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>

#include "dem_format.h"
#include "dem_loader.h"
#include "dem_test_util.h"
#include "test_tiff.h"

namespace aal {
namespace {

class DemLoader : public ::testing::Test {
 protected:
  std::string path(const std::string& name) const { return (dir_.path() / name).string(); }
  test::TempDir dir_;
  test::CapturedWarnings warnings_;
};

constexpr const char* kAsc = "ncols 2\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 5\n1 2\n3 4\n";

TEST_F(DemLoader, FormatComesFromContentNotExtension) {
  test::TestTiff t;
  test::writeTestTiff(path("really_a_tiff.png"), t);
  EXPECT_EQ(detectDemFormat(path("really_a_tiff.png")), DemFormat::GeoTiff);
  EXPECT_EQ(loadDem(path("really_a_tiff.png"), warnings_.options()).format, "TIFF");
  test::writeBytes(path("grid.txt"), kAsc);
  EXPECT_EQ(detectDemFormat(path("grid.txt")), DemFormat::AsciiGrid);
  test::writeBytes(path("x.bin"), std::string("\x89PNG\r\n\x1a\n", 8) + "rest");
  EXPECT_EQ(detectDemFormat(path("x.bin")), DemFormat::Png);
  test::writeBytes(path("y.bin"), std::string("\x76\x2f\x31\x01", 4) + "rest");
  EXPECT_EQ(detectDemFormat(path("y.bin")), DemFormat::OpenExr);
  test::writeBytes(path("Z.HGT"), "anything");
  EXPECT_EQ(detectDemFormat(path("Z.HGT")), DemFormat::Hgt);
  test::writeBytes(path("big.tif"), std::string("II+\0\x08\0\0\0", 8));
  EXPECT_EQ(detectDemFormat(path("big.tif")), DemFormat::GeoTiff);
}

TEST_F(DemLoader, MissingFileIsRefused) {
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("nope.tif")); }),
                      {path("nope.tif"), "no such file"});
}

TEST_F(DemLoader, FolderIsRefused) {
  test::expectMessage(test::inputErrorOf([&] { loadDem(dir_.path().string()); }),
                      {"is a folder, not a DEM file"});
}

TEST_F(DemLoader, EmptyFileIsRefused) {
  test::writeBytes(path("empty.tif"), "");
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("empty.tif")); }),
                      {path("empty.tif"), "file is empty"});
}

TEST_F(DemLoader, UnreadableFileIsRefused) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads any file";
  test::writeBytes(path("locked.asc"), kAsc);
  ::chmod(path("locked.asc").c_str(), 0);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("locked.asc")); }),
                      {path("locked.asc"), "cannot open"});
}

TEST_F(DemLoader, UnknownContentIsRefused) {
  test::writeBytes(path("notes.txt"), "hello, this is not a DEM\n");
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("notes.txt")); }),
                      {path("notes.txt"), "unrecognised DEM format"});
}

TEST_F(DemLoader, ImpostorsOfEachFormatAreRefused) {
  struct Case {
    std::string name, magic, message;
  };
  for (const Case& c :
       {Case{"fake.tif", std::string("II*\0", 4), "not a readable TIFF"},
        Case{"fake.png", std::string("\x89PNG\r\n\x1a\n", 8), "corrupt or truncated PNG"},
        Case{"fake.exr", std::string("\x76\x2f\x31\x01", 4), "corrupt OpenEXR header"}}) {
    test::writeBytes(path(c.name), c.magic + std::string(200, '\x55'));
    test::expectMessage(test::inputErrorOf([&] { loadDem(path(c.name)); }),
                        {path(c.name) + ": " + c.message});
  }
}

TEST_F(DemLoader, InvalidOverridesAreRefused) {
  test::writeBytes(path("g.asc"), kAsc);
  DemLoadOptions o;
  o.cellSizeM = 0.0;
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("g.asc"), o); }), {"--cell-size"});
  o.cellSizeM = std::numeric_limits<double>::quiet_NaN();
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("g.asc"), o); }), {"--cell-size"});
  o.cellSizeM.reset();
  o.zScale = -1.0;
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("g.asc"), o); }), {"--z-scale"});
}

TEST_F(DemLoader, OverridesWinOverTheFile) {
  test::writeBytes(path("g.asc"), kAsc);
  DemLoadOptions o = warnings_.options();
  o.cellSizeM = 2.0;
  o.zScale = 3.0;
  const Heightfield f = loadDem(path("g.asc"), o);
  EXPECT_DOUBLE_EQ(f.cellSizeXM, 2.0);
  EXPECT_DOUBLE_EQ(f.zScale, 3.0);
  EXPECT_EQ(f.at(1, 1), 12.0f);
  EXPECT_EQ(f.source, path("g.asc"));
}

TEST_F(DemLoader, LowerTexelLimitIsHonoured) {
  test::writeBytes(path("g.asc"), kAsc);
  DemLoadOptions o;
  o.maxTexels = 3;
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("g.asc"), o); }),
                      {"has 4 texels, more than the limit of 3"});
}

TEST_F(DemLoader, HeightsBeyondFloatRangeAfterScalingBecomeVoids) {
  test::writeBytes(path("g.asc"), kAsc);
  DemLoadOptions o;
  o.zScale = 1e38;
  const Heightfield f = loadDem(path("g.asc"), o);
  EXPECT_EQ(f.voidCount, 1u);  // 4e38 overflows; 3e38 is still a float
  EXPECT_TRUE(f.isVoid(1, 1));
  EXPECT_TRUE(test::allFinite(f));
}

TEST(DemFormats, HelpNamesEveryFormat) {
  const std::string help = demFormatsHelp();
  for (const char* name : {"GeoTIFF", "hgt", "ASCII", "PNG", "OpenEXR"}) {
    EXPECT_NE(help.find(name), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace aal
