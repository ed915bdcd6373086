// loadDem as a whole: file-level errors, overrides, limits.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"
#include "aperture/terrain/io/dem_summary.h"
#include "aperture/tests/terrain/io/dem_test_util.h"
#include "aperture/tests/terrain/io/gdal_raster.h"

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
  test::GdalRaster r;
  ASSERT_TRUE(test::writeGdalRaster(path("really_a_tiff.png"), r));
  const Heightfield f = loadDem(path("really_a_tiff.png"), warnings_.options());
  EXPECT_EQ(f.format, "GeoTIFF");
  EXPECT_EQ(f.driver, "GTiff");
  test::writeBytes(path("grid.txt"), kAsc);
  EXPECT_EQ(loadDem(path("grid.txt"), warnings_.options()).driver, "AAIGrid");
}

TEST_F(DemLoader, MissingFileIsRefused) {
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("nope.tif")); }),
                      {path("nope.tif"), "no such file"});
}

TEST_F(DemLoader, FolderIsRefused) {
  test::expectMessage(test::inputErrorOf([&] { loadDem(dir_.path().string()); }),
                      {"is a folder, not a DEM file"});
}

// What is not a file is said to be what it is, before GDAL opens it: a
// FIFO's open blocked for ever, a symbolic link loop was "no such file",
// and a MEM::: connection string made GDAL read memory at the address it
// gave (SIGSEGV). SIGALRM ends the test should anything block.
TEST_F(DemLoader, PathsThatAreNotFilesAreRefusedForWhatTheyAre) {
  ::alarm(10);
  ASSERT_EQ(::mkfifo(path("fifo.tif").c_str(), 0644), 0);
  std::filesystem::create_symlink(path("loop2.tif"), path("loop.tif"));
  std::filesystem::create_symlink(path("loop.tif"), path("loop2.tif"));
  EXPECT_EQ(test::inputErrorOf([&] { loadDem(path("fifo.tif")); }),
            path("fifo.tif") + ": is a FIFO, not a file");
  EXPECT_EQ(test::inputErrorOf([&] { loadDem("/dev/zero"); }),
            "/dev/zero: is a character device, not a file");
  EXPECT_EQ(test::inputErrorOf([&] { loadDem(path("loop.tif")); }),
            path("loop.tif") + ": is a symbolic link loop (too many levels of symbolic links)");
  ::alarm(0);
  for (const std::string connection :
       {"MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10", "NUMPY:::0x1", "GTiff:x.tif"}) {
    test::expectMessage(test::inputErrorOf([&] { loadDem(connection); }),
                        {connection + ": is a GDAL connection string", "aperture opens files"});
  }
  test::expectMessage(test::inputErrorOf([&] { loadDem("/vsimem/dem.tif"); }),
                      {"/vsimem/dem.tif: is a path of GDAL's virtual file system /vsimem/"});
  // A file whose name GDAL would take for a connection string is a file:
  // an ASCII grid (not a GeoTIFF, so that every driver is asked, MEM first)
  // in the working folder.
  test::writeBytes(path("MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10"), kAsc);
  const std::filesystem::path before = std::filesystem::current_path();
  std::filesystem::current_path(dir_.path());
  Heightfield field;
  EXPECT_NO_THROW(field = loadDem("MEM:::DATAPOINTER=0x1,PIXELS=10,LINES=10", warnings_.options()));
  std::filesystem::current_path(before);
  EXPECT_EQ(field.driver, "AAIGrid");
  EXPECT_EQ(field.width, 2);
  EXPECT_EQ(field.z[3], 4.0f);
}

TEST_F(DemLoader, EmptyFileIsRefused) {
  test::writeBytes(path("empty.tif"), "");
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("empty.tif")); }),
                      {path("empty.tif"), "is empty"});
}

TEST_F(DemLoader, UnreadableFileIsRefused) {
  if (::geteuid() == 0) GTEST_SKIP() << "root reads any file";
  test::writeBytes(path("locked.asc"), kAsc);
  ::chmod(path("locked.asc").c_str(), 0);
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("locked.asc")); }),
                      {path("locked.asc"), "cannot be read"});
}

TEST_F(DemLoader, UnknownContentIsRefused) {
  test::writeBytes(path("notes.txt"), "hello, this is not a DEM\n");
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("notes.txt")); }),
                      {path("notes.txt"), "not a raster GDAL can read"});
}

TEST_F(DemLoader, ImpostorsOfEachFormatAreRefused) {
  for (const std::string name : {"fake.tif", "fake.png", "fake.hgt", "fake.asc"}) {
    const std::string magic = name == "fake.tif"   ? std::string("II*\0", 4)
                              : name == "fake.png" ? std::string("\x89PNG\r\n\x1a\n", 8)
                                                   : std::string("ncols 3\n");
    test::writeBytes(path(name), magic + std::string(200, '\x55'));
    test::expectMessage(test::inputErrorOf([&] { loadDem(path(name)); }), {path(name) + ": "});
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
  o.zScale.reset();
  for (double bad : {0.0, -2.0, std::numeric_limits<double>::infinity()}) {
    o.exaggeration = bad;
    test::expectMessage(test::inputErrorOf([&] { loadDem(path("g.asc"), o); }), {"--exaggeration"});
  }
}

// A vertical exaggeration multiplies the z scale, so the heights
// and the zScale an aperture map records both carry it.
TEST_F(DemLoader, ExaggerationMultipliesTheZScale) {
  test::writeBytes(path("g.asc"), kAsc);
  DemLoadOptions o = warnings_.options();
  o.zScale = 3.0;
  const Heightfield plain = loadDem(path("g.asc"), o);
  o.exaggeration = 2.5;
  const Heightfield tall = loadDem(path("g.asc"), o);
  EXPECT_DOUBLE_EQ(tall.zScale, 7.5);
  ASSERT_EQ(tall.z.size(), plain.z.size());
  for (size_t i = 0; i < tall.z.size(); ++i) EXPECT_FLOAT_EQ(tall.z[i], 2.5f * plain.z[i]) << i;
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

TEST_F(DemLoader, HeightsBeyondAnyTerrainAreRefusedWithTheirPlace) {
  // A 3e38 m spike (an undeclared fill value) gave its neighbours a full sky.
  test::writeBytes(path("spike.asc"),
                   "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 5\n"
                   "1 2 3\n4 3e38 6\n");
  test::expectMessage(
      test::inputErrorOf([&] { loadDem(path("spike.asc")); }),
      {path("spike.asc"), "height 3e+38 m", "column 1, row 1", "gdal_translate -a_nodata 3"});
  // The bound applies after the z scale: 4 units of 1e6 m is 4000 km.
  test::writeBytes(path("g.asc"), kAsc);
  DemLoadOptions o;
  o.zScale = 1e6;
  test::expectMessage(test::inputErrorOf([&] { loadDem(path("g.asc"), o); }),
                      {"height 2e+06 m (stored 2, z scale 1e+06) at column 1, row 0"});
  o.zScale = 1e5;  // 400 km: far, but a height
  EXPECT_EQ(loadDem(path("g.asc"), o).at(1, 1), 4e5f);
}

TEST_F(DemLoader, NonFiniteHeightsAreVoids) {
  test::GdalRaster r;
  r.width = r.height = 3;
  r.value = [](int, int c, int row) {
    if (c == 1 && row == 0) return std::numeric_limits<double>::quiet_NaN();
    return c == 2 && row == 2 ? -std::numeric_limits<double>::infinity() : 1.0;
  };
  ASSERT_TRUE(test::writeGdalRaster(path("nan.tif"), r));
  const Heightfield f = loadDem(path("nan.tif"), warnings_.options());
  EXPECT_EQ(f.voidCount, 2u);
  EXPECT_TRUE(f.isVoid(1, 0));
  EXPECT_TRUE(f.isVoid(2, 2));
  EXPECT_TRUE(test::allFinite(f));
}

// Sets AAL_MEMORY_LIMIT for one test.
class MemoryLimit {
 public:
  explicit MemoryLimit(const char* value) { setenv("AAL_MEMORY_LIMIT", value, 1); }
  ~MemoryLimit() { unsetenv("AAL_MEMORY_LIMIT"); }
};

test::GdalRaster bumpyWithVoids() {
  test::GdalRaster r;
  r.width = 300;
  r.height = 200;
  r.value = [](int, int c, int row) {
    if ((c * 7 + row * 3) % 41 == 0) return -9999.0;
    return std::sin(0.05 * c) * 100.0 + row * 0.5 + (c == 250 && row == 170 ? 900.0 : 0.0);
  };
  r.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValue(-9999); };
  return r;
}

TEST_F(DemLoader, MemoryBeyondTheLimitIsRefusedWithTheNumbers) {
  ASSERT_TRUE(test::writeGdalRaster(path("d.tif"), bumpyWithVoids()));
  const MemoryLimit limit("100K");
  // 300 x 200 texels of 5 bytes: 300 kB.
  test::expectMessage(
      test::inputErrorOf([&] { loadDem(path("d.tif")); }),
      {path("d.tif"), "holding its 300 x 200 heights and void mask needs 300 kB",
       "only 102 kB of memory is available (AAL_MEMORY_LIMIT)", "gdal_translate -srcwin"});
  // A summary reads bands that fit.
  const DemSource source(path("d.tif"), {});
  EXPECT_NO_THROW(summarizeDem(source, demGeometry(source, {}), 16 << 10));
}

TEST_F(DemLoader, MemoryLimitMustBeASize) {
  ASSERT_TRUE(test::writeGdalRaster(path("d.tif"), bumpyWithVoids()));
  for (const char* bad : {"abc", "-5", "0", "12Q", "1e30G"}) {
    const MemoryLimit limit(bad);
    test::expectMessage(test::inputErrorOf([&] { loadDem(path("d.tif")); }),
                        {"AAL_MEMORY_LIMIT must be a positive size", bad});
  }
  const MemoryLimit limit("2M");
  EXPECT_EQ(loadDem(path("d.tif")).width, 300);
}

TEST_F(DemLoader, SummaryInBandsEqualsTheWholeLoad) {
  ASSERT_TRUE(test::writeGdalRaster(path("d.tif"), bumpyWithVoids()));
  const Heightfield whole = loadDem(path("d.tif"));
  float lo = 1e30f, hi = -1e30f;
  for (size_t i = 0; i < whole.z.size(); ++i) {
    if (whole.voidMask[i]) continue;
    lo = std::min(lo, whole.z[i]);
    hi = std::max(hi, whole.z[i]);
  }
  ASSERT_GT(whole.voidCount, 1000u);
  const DemSource source(path("d.tif"), {});
  // One row per band, and all at once.
  for (const size_t bandBytes : {size_t{1}, size_t{64} << 20}) {
    const DemSummary s = summarizeDem(source, demGeometry(source, {}), bandBytes);
    EXPECT_EQ(s.voids, whole.voidCount);
    EXPECT_EQ(s.zMinM, lo);
    EXPECT_EQ(s.zMaxM, hi);
  }
  EXPECT_GT(hi, 950.0f);  // the spike at row 170 is in a late band
}

TEST_F(DemLoader, SummaryRefusesASpikeNamingItsRow) {
  test::GdalRaster r = bumpyWithVoids();
  r.value = [](int, int c, int row) { return c == 3 && row == 150 ? 3e38 : 1.0; };
  ASSERT_TRUE(test::writeGdalRaster(path("spike.tif"), r));
  const DemSource source(path("spike.tif"), {});
  test::expectMessage(test::inputErrorOf([&] { summarizeDem(source, demGeometry(source, {}), 1); }),
                      {"at column 3, row 150 is beyond any terrain"});
}

TEST(DemFormats, HelpNamesTheCommonFormatsAndTheWayOut) {
  const std::string help = demFormatsHelp();
  for (const char* name : {"GDAL", "GeoTIFF", "hgt", "ASCII", "VRT", "PNG", "gdal_translate -b"}) {
    EXPECT_NE(help.find(name), std::string::npos) << name;
  }
}

}  // namespace
}  // namespace aal
