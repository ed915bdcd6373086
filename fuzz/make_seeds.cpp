// Writes small seed inputs for the fuzz targets into OUT/<target>/, so that
// no binary corpus is committed: fuzz_seeds OUT. The files are made with
// GDAL's own drivers (tests/terrain/io/gdal_raster.h describes them).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "aperture/tests/terrain/io/gdal_raster.h"
#include "aperture/tests/terrain/io/hostile_files.h"

namespace fs = std::filesystem;

namespace {

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

void writeFile(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

aal::test::GdalRaster placed(const char* crs, double x, double y, double step) {
  aal::test::GdalRaster r;
  r.width = 9;
  r.height = 7;
  r.hasTransform = true;
  const double t[6] = {x, step, 0, y, 0, -step};
  std::copy(t, t + 6, r.transform);
  r.crs = crs;
  return r;
}

constexpr const char* kAsciiGrid =
    "ncols 4\nnrows 3\nxllcorner 1000\nyllcorner 2000\ncellsize 10\nNODATA_value -9999\n"
    "1 2 3 4\n5 -9999 7.5 8\n9 10 nan -12.25\n";

}  // namespace

// gtest's ADD_FAILURE in gdal_raster.h needs a test; outside one it prints.
int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT\n");
    return 2;
  }
  const fs::path out = argv[1];
  for (const char* target : {"load_dem", "raster"}) fs::create_directories(out / target);
  const fs::path scratch = out / "scratch";
  fs::create_directories(scratch);
  // load_dem: a file-name selector byte (0 .tif, 2 .asc, 3 .png), then the file.
  const auto seed = [&](const std::string& name, char selector, const aal::test::GdalRaster& r,
                        const std::string& driver) {
    const fs::path file = scratch / name;
    if (!aal::test::writeGdalRaster(file.string(), r, driver)) {
      std::fprintf(stderr, "fuzz_seeds: cannot write %s\n", file.c_str());
      std::exit(1);
    }
    writeFile(out / "load_dem" / name, std::string(1, selector) + readFile(file));
  };
  aal::test::GdalRaster geographic = placed("EPSG:4326", -84.4, 36.7, 1.0 / 1200);
  geographic.type = GDT_Int16;
  geographic.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValue(-32768); };
  seed("geographic_int16.tif", 0, geographic, "GTiff");
  aal::test::GdalRaster utm = placed("EPSG:32616", 740000, 4050000, 10);
  utm.creationOptions = {"TILED=YES", "BLOCKXSIZE=16", "BLOCKYSIZE=16", "COMPRESS=DEFLATE",
                         "PREDICTOR=3"};
  utm.extra = [](GDALDataset& ds) {
    ds.GetRasterBand(1)->SetScale(0.5);
    ds.GetRasterBand(1)->SetUnitType("ft");
  };
  seed("utm_float_tiled.tif", 0, utm, "GTiff");
  aal::test::GdalRaster alpha = placed("EPSG:3857", 1e6, 8e6, 100);
  alpha.bands = 2;
  alpha.value = [](int band, int c, int row) { return band == 2 ? (c > 2) * 255.0 : c * row; };
  alpha.extra = [](GDALDataset& ds) { ds.GetRasterBand(2)->SetColorInterpretation(GCI_AlphaBand); };
  alpha.creationOptions = {"ALPHA=YES"};
  seed("mercator_alpha.tif", 0, alpha, "GTiff");
  aal::test::GdalRaster png;
  png.type = GDT_UInt16;
  png.extra = [](GDALDataset& ds) { ds.GetRasterBand(1)->SetNoDataValue(0); };
  seed("image.png", 3, png, "PNG");
  writeFile(out / "load_dem" / "grid.asc", std::string("\x02", 1) + kAsciiGrid);
  // The oversize cases: headers that claim more than their files hold.
  writeFile(out / "load_dem" / "shared_strips.tif",
            std::string("\x00", 1) + aal::test::sharedStripTiff(64, 256));
  writeFile(out / "load_dem" / "claims.png",
            std::string("\x03", 1) + aal::test::pngClaiming(40000, 40000));
  aal::test::GdalRaster far = placed("EPSG:3857", 1e18, 80, 30);
  seed("far_mercator.tif", 0, far, "GTiff");
  fs::remove_all(scratch);

  // raster: bytes the FuzzedDataProvider turns into a raster description.
  std::mt19937 random(7);
  for (int i = 0; i < 8; ++i) {
    std::string bytes(256 + 64 * i, '\0');
    for (char& b : bytes) b = static_cast<char>(random());
    writeFile(out / "raster" / ("random_" + std::to_string(i)), bytes);
  }
  std::printf("fuzz_seeds: wrote seeds to %s\n", out.c_str());
  return 0;
}
