// aal-bake --openness-positive and --openness-negative: the rasters, their
// refusals, and the comparison with SAGA's Topographic Openness where
// saga_cmd is installed (docs/baking.md, "Openness").
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/synthetic.h"
#include "aperture/tests/tools/run_tool.h"
#include "aperture/tests/tools/void_dem.h"

namespace aal {
namespace {

namespace fs = std::filesystem;
using test::quoted;
using test::runTool;
using test::TempDir;

constexpr float kNodata = test::kVoidDemNodata;
using test::isVoid;
using test::utm;
using test::writeDemWithVoids;

TEST(AalBakeOpenness, WritesBothRastersPlacedLikeTheDem) {
  TempDir dir;
  const fs::path dem = writeDemWithVoids(dir);
  const fs::path pos = dir.path() / "pos.tif", neg = dir.path() / "neg.tif";
  const auto r =
      runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") +
                              " -q --azimuths 16 --max-distance 300" + " --openness-positive " +
                              quoted(pos) + " --openness-negative " + quoted(neg));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  // What the library gives for the DEM as aal-bake reads it.
  const Heightfield field = loadDem(dem.string());
  BakeOptions o;
  o.azimuths = 16;
  o.maxDistanceM = 300;
  o.positiveOpenness = o.negativeOpenness = true;
  const BakeResult expected = bakeApertures(field, o);
  for (const auto& [path, values] :
       {std::pair{pos, expected.positiveOpenness}, std::pair{neg, expected.negativeOpenness}}) {
    const Heightfield written = loadDem(path.string());
    EXPECT_EQ(written.geo.epsg, 32616);
    ASSERT_EQ(written.width, 40);
    ASSERT_EQ(written.height, 40);
    for (int row = 0; row < 40; ++row) {
      for (int col = 0; col < 40; ++col) {
        const bool ring = row == 0 || col == 0 || row == 39 || col == 39;
        // Nodata at the DEM's voids, and on the outer ring (an open edge).
        ASSERT_EQ(written.isVoid(col, row), ring || isVoid(col, row)) << col << "," << row;
        if (written.isVoid(col, row)) continue;
        ASSERT_EQ(written.at(col, row), values[field.index(col, row)]) << col << "," << row;
        ASSERT_GT(written.at(col, row), 0.0f);
        ASSERT_LT(written.at(col, row), 180.0f);
      }
    }
  }
}

TEST(AalBakeOpenness, RefusalsExitWithTwoAndWriteNothing) {
  TempDir dir;
  const fs::path dem = writeDemWithVoids(dir);
  const std::string pos = " --openness-positive " + quoted(dir.path() / "p.tif");
  const std::string neg = " --openness-negative " + quoted(dir.path() / "n.tif");
  const std::string in = quoted(dem) + " -q -o " + quoted(dir.path() / "a.exr");
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {
           Case{quoted(dem) + " -q -o " + quoted(dir.path() / "tiles") + " --tile-size 16" + pos,
                "writes no --openness-positive, --openness-negative or --local-dominance"},
           Case{in + " --method rays" + neg, "need --method sweep"},
           Case{in + " --curvature" + neg, "--openness-negative does not take --curvature"},
           Case{in + " --openness-positive " + quoted(dir.path() / "no" / "p.tif"),
                "does not exist"},
           Case{in + pos + " --svf " + quoted(dir.path() / "p.tif"), "is also the output of"},
           Case{in + " --openness-negative " + quoted(dem), "is the input DEM"},
       }) {
    const auto r = runTool("aal-bake", c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << "\n" << r.out;
  }
  for (const char* name : {"a.exr", "p.tif", "n.tif", "tiles"}) {
    EXPECT_FALSE(fs::exists(dir.path() / name)) << name;
  }
}

// Positive openness with --curvature: the sweep's own horizons, dropped.
TEST(AalBakeOpenness, PositiveTakesCurvature) {
  TempDir dir;
  const fs::path dem = writeDemWithVoids(dir);
  const auto r =
      runTool("aal-bake", quoted(dem) + " -q -o " + quoted(dir.path() / "a.exr") +
                              " --curvature --openness-positive " + quoted(dir.path() / "p.tif"));
  EXPECT_EQ(r.exitCode, 0) << r.out;
  EXPECT_TRUE(fs::exists(dir.path() / "p.tif"));
}

// Band 1 of a raster, nodata as NaN.
std::vector<double> readBand(const fs::path& path, int& width, int& height) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return {};
  width = ds->GetRasterXSize();
  height = ds->GetRasterYSize();
  GDALRasterBand* band = ds->GetRasterBand(1);
  std::vector<double> values(size_t(width) * height);
  const CPLErr err =
      band->RasterIO(GF_Read, 0, 0, width, height, values.data(), width, height, GDT_Float64, 0, 0);
  int hasNodata = 0;
  const double nodata = band->GetNoDataValue(&hasNodata);
  GDALClose(ds);
  if (err != CE_None) return {};
  for (double& v : values) {
    if (hasNodata && v == nodata) v = NAN;
  }
  return values;
}

struct Agreement {
  double meanAbs = 0, max = 0, correlation = 0;
  size_t count = 0;
};

// Over the texels at least `margin` from every edge and finite in both.
Agreement agreement(const std::vector<double>& a, const std::vector<double>& b, int width,
                    int height, int margin) {
  double sa = 0, sb = 0, saa = 0, sbb = 0, sab = 0;
  Agreement g;
  for (int row = margin; row < height - margin; ++row) {
    for (int col = margin; col < width - margin; ++col) {
      const size_t i = size_t(row) * width + col;
      if (!std::isfinite(a[i]) || !std::isfinite(b[i])) continue;
      const double d = std::abs(a[i] - b[i]);
      g.meanAbs += d;
      g.max = std::max(g.max, d);
      sa += a[i], sb += b[i], saa += a[i] * a[i], sbb += b[i] * b[i], sab += a[i] * b[i];
      ++g.count;
    }
  }
  const double n = double(g.count);
  g.meanAbs /= n;
  g.correlation = (sab - sa * sb / n) / std::sqrt((saa - sa * sa / n) * (sbb - sb * sb / n));
  return g;
}

// How SAGA and GRASS are run: without the sanitizer build's LD_PRELOAD
// (scripts/test.sh), under which AddressSanitizer reports SAGA's own bugs.
const std::string kOtherTool = "env -u LD_PRELOAD ";

// The DEM both SAGA comparisons read: kSagaCropSize² texels of the
// Jacksboro DEM placed on a square 90 m grid.
constexpr int kSagaCropSize = 256;
fs::path writeJacksboroCrop(const TempDir& dir) {
  const Heightfield jacksboro =
      loadDem((fs::path(AAL_TEST_SOURCE_DIR) / "heightmaps" / "jacksboro_fault_dem.tif").string());
  const int size = kSagaCropSize;
  std::vector<float> crop(size_t(size) * size);
  for (int row = 0; row < size; ++row) {
    for (int col = 0; col < size; ++col) crop[size_t(row) * size + col] = jacksboro.at(col, row);
  }
  const fs::path dem = dir.path() / "dem.tif";
  writeFloatGeoTiff(dem.string(), size, size, crop.data(), utm(90));
  return dem;
}

// SAGA's Topographic Openness (ta_lighting 5, line tracing) on real terrain:
// 256 x 256 texels of the Jacksboro DEM placed on a square 90 m grid, 16
// directions, a radius of 1800 m (20 cells). SAGA steps one cell at a time
// and takes the nearest texel with the distance walked, not the texel's
// own: its angles differ from the sweep's near the texel, by 0.6° on
// average here (docs/baking.md, "Openness").
TEST(AalBakeOpenness, AgreesWithSaga) {
  if (std::system("command -v saga_cmd >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "saga_cmd is not installed (scripts/install-deps.sh installs saga)";
  }
  TempDir dir;
  const int size = kSagaCropSize;
  const fs::path dem = writeJacksboroCrop(dir);
  const fs::path pos = dir.path() / "pos.tif", neg = dir.path() / "neg.tif";
  const auto r =
      runTool("aal-bake", quoted(dem) + " -q -o " + quoted(dir.path() / "a.exr") +
                              " --azimuths 16 --max-distance 1800" + " --openness-positive " +
                              quoted(pos) + " --openness-negative " + quoted(neg));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const fs::path sagaPos = dir.path() / "saga_pos.tif", sagaNeg = dir.path() / "saga_neg.tif";
  const auto saga = test::runShell(kOtherTool + "saga_cmd ta_lighting 5 -DEM " + quoted(dem) +
                                   " -POS " + quoted(sagaPos) + " -NEG " + quoted(sagaNeg) +
                                   " -RADIUS 1800 -DIRECTIONS 1 -NDIRS 16 -METHOD 1 -UNIT 1"
                                   " -NADIR 1");
  ASSERT_EQ(saga.exitCode, 0) << saga.out;
  for (const auto& [ours, theirs] : {std::pair{pos, sagaPos}, std::pair{neg, sagaNeg}}) {
    int w = 0, h = 0, sw = 0, sh = 0;
    const std::vector<double> a = readBand(ours, w, h), b = readBand(theirs, sw, sh);
    ASSERT_EQ(a.size(), size_t(size) * size) << ours;
    ASSERT_EQ(b.size(), a.size()) << theirs;
    const Agreement g = agreement(a, b, size, size, 20);
    std::printf(
        "%s against SAGA: mean |difference| %.3f°, max %.3f°, correlation %.4f (%zu texels)\n",
        ours.filename().c_str(), g.meanAbs, g.max, g.correlation, g.count);
    EXPECT_GT(g.count, size_t(200 * 200));
    EXPECT_LE(g.meanAbs, 1.0) << ours;
    EXPECT_GE(g.correlation, 0.99) << ours;
  }
}

// aal-bake's sky-view factor of the crop (16 directions, 1800 m), the
// raster alone.
fs::path bakeCropSkyViewFactor(const TempDir& dir, const fs::path& dem) {
  const fs::path svf = dir.path() / "svf.tif";
  const auto r = runTool(
      "aal-bake", quoted(dem) + " -q --azimuths 16 --max-distance 1800 --svf " + quoted(svf));
  EXPECT_EQ(r.exitCode, 0) << r.out;
  return svf;
}

// Prints how `theirs` (times `scale`) agrees with aal-bake's sky-view factor
// `ours` on the crop, 20 texels from the edges left out, and checks it.
void expectSkyViewFactorAgreement(const fs::path& ours, const fs::path& theirs, double scale,
                                  const char* against, double maxMeanAbs) {
  const int size = kSagaCropSize;
  int w = 0, h = 0, tw = 0, th = 0;
  const std::vector<double> a = readBand(ours, w, h);
  std::vector<double> b = readBand(theirs, tw, th);
  ASSERT_EQ(a.size(), size_t(size) * size);
  ASSERT_EQ(b.size(), a.size());
  for (double& v : b) v *= scale;
  const Agreement g = agreement(a, b, size, size, 20);
  std::printf(
      "sky-view factor against %s: mean |difference| %.4f, max %.4f, correlation %.4f (%zu "
      "texels)\n",
      against, g.meanAbs, g.max, g.correlation, g.count);
  EXPECT_GT(g.count, size_t(200 * 200));
  EXPECT_LE(g.meanAbs, maxMeanAbs);
  EXPECT_GE(g.correlation, 0.99);
}

// The sky-view factor (Zaksek et al. 2011: 1 - mean sin of the horizon
// clamped at the horizontal) is what SAGA calls Visible Sky (ta_lighting 3,
// in percent); SAGA's own "Sky View Factor" weights the sky by the cosine to
// the slope's normal (Haentzschel et al. 2005) and is another quantity. On
// the crop above, 16 directions, 1800 m: mean |difference| 0.040 (SAGA's
// sampling, as for openness: its horizons lie lower), correlation 0.995
// (docs/gis.md, "Outputs against other tools").
TEST(AalBakeOpenness, SkyViewFactorIsSagasVisibleSky) {
  if (std::system("command -v saga_cmd >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "saga_cmd is not installed (scripts/install-deps.sh installs saga)";
  }
  TempDir dir;
  const fs::path dem = writeJacksboroCrop(dir);
  const fs::path svf = bakeCropSkyViewFactor(dir, dem);
  const fs::path sagaVisible = dir.path() / "saga_visible.tif";
  const auto saga =
      test::runShell(kOtherTool + "saga_cmd ta_lighting 3 -DEM " + quoted(dem) + " -VISIBLE " +
                     quoted(sagaVisible) + " -SVF " + quoted(dir.path() / "saga_svf.tif") +
                     " -RADIUS 1800 -NDIRS 16 -METHOD 0");
  ASSERT_EQ(saga.exitCode, 0) << saga.out;
  expectSkyViewFactorAgreement(svf, sagaVisible, 0.01, "SAGA's Visible Sky", 0.05);  // percent
}

// GRASS's r.horizon (horizon angles per direction, counter-clockwise from
// east, to the radius) turned into the same 1 - mean sin(max(h, 0)) agrees
// with aal-bake's sky-view factor far more closely than SAGA: r.horizon
// interpolates the heights along its rays. On the crop above, 16 directions,
// 1800 m: mean |difference| 0.0041, largest 0.042, correlation 0.996
// (docs/baking.md, "Sky-view factor against SAGA and GRASS").
TEST(AalBakeOpenness, SkyViewFactorAgreesWithGrassRHorizon) {
  if (std::system("command -v grass >/dev/null 2>&1") != 0) {
    GTEST_SKIP() << "grass is not installed (scripts/install-deps.sh installs grass-core)";
  }
  TempDir dir;
  const fs::path dem = writeJacksboroCrop(dir);
  const fs::path svf = bakeCropSkyViewFactor(dir, dem);
  const fs::path grassSvf = dir.path() / "grass_svf.tif", location = dir.path() / "grass";
  std::string terms;
  for (const char* a : {"000_0", "022_5", "045_0", "067_5", "090_0", "112_5", "135_0", "157_5",
                        "180_0", "202_5", "225_0", "247_5", "270_0", "292_5", "315_0", "337_5"}) {
    terms += std::string(terms.empty() ? "" : "+") + "sin(max(hor_" + a + ",0))";
  }
  const fs::path script = dir.path() / "svf.sh";
  std::ofstream(script) << "set -e\n"
                        << "r.in.gdal input=" << quoted(dem) << " output=dem --q\n"
                        << "g.region raster=dem\n"
                        << "r.horizon -d elevation=dem step=22.5 maxdistance=1800 output=hor --q\n"
                        << "r.mapcalc expression='svf = 1.0 - (" << terms << ") / 16' --q\n"
                        << "r.out.gdal input=svf output=" << quoted(grassSvf)
                        << " type=Float64 -c --q\n";
  const std::string home = kOtherTool + "HOME=" + quoted(dir.path());
  const auto grass =
      test::runShell(home + " grass -c " + quoted(dem) + " " + quoted(location) + " -e && " + home +
                     " grass " + quoted(location / "PERMANENT") + " --exec bash " + quoted(script));
  ASSERT_EQ(grass.exitCode, 0) << grass.out;
  expectSkyViewFactorAgreement(svf, grassSvf, 1.0, "GRASS r.horizon", 0.01);
}

// The openness's own nodata (the outer ring) is the raster's nodata value,
// NaN, as are the DEM's voids, whatever nodata value the DEM declares (a float
// raster's convention, docs/dem-input.md, "Output: GIS rasters").
TEST(AalBakeOpenness, TheOuterRingIsTheRastersNodata) {
  TempDir dir;
  const fs::path withVoids = writeDemWithVoids(dir);
  SyntheticTerrainOptions s;
  s.width = s.height = 24;
  s.cellSizeM = 30;
  const Heightfield plain = makeSyntheticTerrain(s);
  const fs::path noNodata = dir.path() / "plain.tif";
  writeFloatGeoTiff(noNodata.string(), 24, 24, plain.z.data(), utm(30));
  for (const fs::path& dem : {withVoids, noNodata}) {
    const fs::path pos = dir.path() / "pos.tif";
    const auto r =
        runTool("aal-bake", quoted(dem) + " -q --azimuths 8 -o " + quoted(dir.path() / "a.exr") +
                                " --openness-positive " + quoted(pos));
    ASSERT_EQ(r.exitCode, 0) << r.out;
    GDALAllRegister();
    GDALDataset* ds = GDALDataset::Open(pos.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
    ASSERT_NE(ds, nullptr);
    const int width = ds->GetRasterXSize();
    int hasNodata = 0;
    const double declared = ds->GetRasterBand(1)->GetNoDataValue(&hasNodata);
    float corner = 0, inside = 0;
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, 1, 1, &corner, 1, 1, GDT_Float32, 0, 0),
              CE_None);
    EXPECT_EQ(ds->GetRasterBand(1)->RasterIO(GF_Read, width / 2, 3, 1, 1, &inside, 1, 1,
                                             GDT_Float32, 0, 0),
              CE_None);
    GDALClose(ds);
    ASSERT_TRUE(hasNodata) << dem;
    EXPECT_TRUE(std::isnan(declared) && std::isnan(corner)) << dem;
    EXPECT_TRUE(std::isfinite(inside) && inside != float(kNodata)) << dem;
  }
}

}  // namespace
}  // namespace aal
