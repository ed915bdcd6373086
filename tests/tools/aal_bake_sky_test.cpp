// aal-bake --svf-anisotropic and --sky-illumination: the rasters, their
// band names, and their refusals (docs/baking.md, "Anisotropic sky-view
// factor" and "Sky illumination").
#include <gdal_priv.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
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

std::string bandDescription(const fs::path& path) {
  GDALAllRegister();
  GDALDataset* ds = GDALDataset::Open(path.string().c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY);
  if (!ds) return "";
  const std::string description = ds->GetRasterBand(1)->GetDescription();
  GDALClose(ds);
  return description;
}

TEST(AalBakeSky, WritesBothRastersPlacedLikeTheDem) {
  TempDir dir;
  const fs::path dem = writeDemWithVoids(dir);
  const fs::path asvf = dir.path() / "asvf.tif", sky = dir.path() / "sky.tif";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") +
                                         " -q --azimuths 16 --max-distance 300" +
                                         " --svf-anisotropic " + quoted(asvf) +
                                         " --svf-anisotropy-direction 45 --svf-anisotropy-level "
                                         "high --sky-illumination " +
                                         quoted(sky) + " --sky-model uniform");
  ASSERT_EQ(r.exitCode, 0) << r.out;
  // What the library gives for the DEM as aal-bake reads it.
  const Heightfield field = loadDem(dem.string());
  BakeOptions o;
  o.azimuths = 16;
  o.maxDistanceM = 300;
  o.anisotropicSkyViewFactor = o.skyIllumination = true;
  o.anisotropy = anisotropyLevel(true, 45);
  o.skyModel = SkyModel::Uniform;
  const BakeResult expected = bakeApertures(field, o);
  for (const auto& [path, values] : {std::pair{asvf, expected.anisotropicSkyViewFactor},
                                     std::pair{sky, expected.skyIllumination}}) {
    const Heightfield written = loadDem(path.string());
    EXPECT_EQ(written.geo.epsg, 32616);
    ASSERT_EQ(written.width, 40);
    ASSERT_EQ(written.height, 40);
    for (int row = 0; row < 40; ++row) {
      for (int col = 0; col < 40; ++col) {
        ASSERT_EQ(written.isVoid(col, row), isVoid(col, row)) << col << "," << row;
        if (written.isVoid(col, row)) continue;
        ASSERT_EQ(written.at(col, row), values[field.index(col, row)]) << col << "," << row;
        ASSERT_GT(written.at(col, row), 0.0f);
        ASSERT_LE(written.at(col, row), 1.000001f);
      }
    }
  }
  EXPECT_EQ(bandDescription(asvf), "anisotropic sky-view factor");
  EXPECT_EQ(bandDescription(sky), "sky illumination (uniform sky, 1 = open horizontal plane)");
}

// The default: the overcast sky, and RVT's low level towards 315°.
TEST(AalBakeSky, DefaultsToTheOvercastSkyAndTheLowLevel) {
  TempDir dir;
  const fs::path dem = writeDemWithVoids(dir);
  const fs::path asvf = dir.path() / "asvf.tif", sky = dir.path() / "sky.tif";
  const auto r = runTool("aal-bake", quoted(dem) + " -o " + quoted(dir.path() / "a.exr") +
                                         " -q --azimuths 16 --svf-anisotropic " + quoted(asvf) +
                                         " --sky-illumination " + quoted(sky));
  ASSERT_EQ(r.exitCode, 0) << r.out;
  const Heightfield field = loadDem(dem.string());
  BakeOptions o;
  o.azimuths = 16;
  o.anisotropicSkyViewFactor = o.skyIllumination = true;
  const BakeResult expected = bakeApertures(field, o);
  const Heightfield a = loadDem(asvf.string()), s = loadDem(sky.string());
  for (const size_t i : {field.index(5, 5), field.index(30, 25)}) {
    EXPECT_EQ(a.z[i], expected.anisotropicSkyViewFactor[i]);
    EXPECT_EQ(s.z[i], expected.skyIllumination[i]);
  }
  EXPECT_EQ(bandDescription(sky), "sky illumination (CIE overcast sky, 1 = open horizontal plane)");
}

TEST(AalBakeSky, RefusalsExitWithTwoAndWriteNothing) {
  TempDir dir;
  const fs::path dem = writeDemWithVoids(dir);
  const std::string asvf = " --svf-anisotropic " + quoted(dir.path() / "as.tif");
  const std::string sky = " --sky-illumination " + quoted(dir.path() / "sk.tif");
  const std::string in = quoted(dem) + " -q -o " + quoted(dir.path() / "a.exr");
  struct Case {
    std::string args, says;
  };
  for (const Case& c : {
           Case{quoted(dem) + " -q -o " + quoted(dir.path() / "tiles") + " --tile-size 16" + sky,
                "writes no --svf-anisotropic or --sky-illumination"},
           Case{quoted(dem) + " -q -o " + quoted(dir.path() / "tiles") + " --tile-size 16" + asvf,
                "writes no --svf-anisotropic or --sky-illumination"},
           Case{in + " --method rays" + sky, "need --method sweep"},
           Case{in + " --method rays" + asvf, "need --method sweep"},
           Case{in + " --sky-model overcast", "requires --sky-illumination"},
           Case{in + " --svf-anisotropy-level high", "requires --svf-anisotropic"},
           Case{in + asvf + " --svf-anisotropy-direction 400", "--svf-anisotropy-direction"},
           Case{in + sky + " --sky-model clear", "--sky-model"},
           Case{in + sky + " --svf-anisotropic " + quoted(dir.path() / "sk.tif"),
                "is also the output of"},
           Case{in + " --sky-illumination " + quoted(dem), "is the input DEM"},
       }) {
    const auto r = runTool("aal-bake", c.args);
    EXPECT_EQ(r.exitCode, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.says), std::string::npos) << c.args << "\n" << r.out;
  }
  for (const char* name : {"a.exr", "as.tif", "sk.tif", "tiles"}) {
    EXPECT_FALSE(fs::exists(dir.path() / name)) << name;
  }
}

}  // namespace
}  // namespace aal
