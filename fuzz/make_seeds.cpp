// Writes small seed inputs for the fuzz targets into OUT/<target>/, so that
// no binary corpus is committed: fuzz_seeds OUT
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "geotiff_writer.h"
#include "test_tiff.h"

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

// GeoTIFF seeds: the layouts and georeferencing variants the reader handles.
std::vector<fs::path> writeTiffSeeds(const fs::path& dir) {
  using aal::test::SampleKind;
  using aal::test::TestTiff;
  std::vector<fs::path> files;
  const auto add = [&](const std::string& name, const TestTiff& t) {
    files.push_back(dir / name);
    aal::test::writeTestTiff(files.back(), t);
  };
  TestTiff geographic;
  geographic.width = 8;
  geographic.height = 6;
  geographic.kind = SampleKind::Int16;
  geographic.modelType = 2;
  geographic.rasterType = 1;
  geographic.geographicType = 4326;
  geographic.pixelScale = {1.0 / 1200, 1.0 / 1200, 0};
  geographic.tiePoints = {0, 0, 0, -84.4, 36.7, 0};
  geographic.values = aal::test::rampValues(8, 6);
  geographic.values[5] = -32768;
  geographic.gdalNodata = "-32768";
  add("geographic_int16.tif", geographic);

  TestTiff tiled = geographic;
  tiled.kind = SampleKind::Float32;
  tiled.tiled = true;
  tiled.compression = COMPRESSION_ADOBE_DEFLATE;
  tiled.rasterType = 2;
  tiled.width = 20;
  tiled.height = 17;
  tiled.values = aal::test::rampValues(20, 17, 0.25);
  tiled.gdalNodata.reset();
  add("tiled_float_point.tif", tiled);

  TestTiff projected;
  projected.kind = SampleKind::UInt16;
  projected.modelType = 1;
  projected.projectedType = 32616;
  projected.linearUnits = 9002;
  projected.verticalUnits = 9002;
  projected.pixelScale = {10, -10, 0};
  projected.tiePoints = {0, 0, 0, 740000, 4050000, 0};
  projected.values = aal::test::rampValues(projected.width, projected.height);
  for (double& v : projected.values) v += 100;
  add("projected_southup_feet.tif", projected);

  TestTiff transform;
  transform.kind = SampleKind::Float64;
  transform.modelType = 1;
  transform.transformation = {20, 0, 0, 700000, 0, -25, 0, 4000000, 0, 0, 0, 0, 0, 0, 0, 1};
  transform.samplesPerPixel = 2;
  transform.compression = COMPRESSION_LZW;
  transform.overviews = 1;
  add("transform_twoband.tif", transform);

  files.push_back(dir / "writer_float.tif");
  const std::vector<float> z = {1, 2, 3, std::numeric_limits<float>::quiet_NaN(), 5, 6};
  aal::GeoReference geo;
  geo.crs = aal::CrsKind::Projected;
  geo.stepX = geo.stepY = 30;
  aal::writeFloatGeoTiff(files.back().string(), 3, 2, z.data(), geo);
  return files;
}

void writeImage(const fs::path& path, OIIO::TypeDesc type, int channels) {
  std::vector<float> pixels(static_cast<size_t>(6 * 5 * channels));
  for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<float>(i % 7) / 7.0f;
  std::unique_ptr<OIIO::ImageOutput> out = OIIO::ImageOutput::create(path.string());
  if (!out || !out->open(path.string(), OIIO::ImageSpec(6, 5, channels, type)) ||
      !out->write_image(OIIO::TypeDesc::FLOAT, pixels.data())) {
    std::fprintf(stderr, "fuzz_seeds: cannot write %s\n", path.c_str());
    std::exit(1);
  }
}

constexpr const char* kAsciiGrid =
    "ncols 4\nnrows 3\nxllcorner 1000\nyllcorner 2000\ncellsize 10\nNODATA_value -9999\n"
    "1 2 3 4\n5 -9999 7.5 8\n9 10 nan -12.25\n";
constexpr const char* kPrj =
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"
    "UNIT[\"degree\",0.0174532925199433],AUTHORITY[\"EPSG\",\"4326\"]]";

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT\n");
    return 2;
  }
  const fs::path out = argv[1];
  for (const char* target : {"geotiff", "hgt", "ascii_grid", "load_dem"}) {
    fs::create_directories(out / target);
  }
  const std::vector<fs::path> tiffs = writeTiffSeeds(out / "geotiff");

  // hgt: name length, name, flags ('T': repeat to a full tile), bytes.
  const std::string name = "N36W085.hgt";
  const std::string samples("\x01\x2c\x80\x00\x02\x58\x00\x00\xff\xf6", 10);  // 300, void, ...
  writeFile(out / "hgt" / "tile",
            std::string(1, static_cast<char>(name.size())) + name + "T" + samples);
  writeFile(out / "hgt" / "short",
            std::string(1, static_cast<char>(name.size())) + name + "\x00" + samples);
  writeFile(out / "hgt" / "south", std::string("\x0bS12E130.hgtT", 13) + samples);

  writeFile(out / "ascii_grid" / "corner", kAsciiGrid);
  writeFile(out / "ascii_grid" / "centre_prj",
            std::string("NCOLS 2\nNROWS 2\nXLLCENTER -85\nYLLCENTER 36\nDX 0.001\nDY 0.001\n"
                        "1 2\n3 4\n") +
                '\0' + kPrj);

  // load_dem: extension selector byte, then the file.
  for (const fs::path& tiff : tiffs) {
    writeFile(out / "load_dem" / tiff.filename(), std::string("\x00", 1) + readFile(tiff));
  }
  writeFile(out / "load_dem" / "grid.asc", std::string("\x02", 1) + kAsciiGrid);
  const fs::path png = out / "load_dem" / "tmp.png", exr = out / "load_dem" / "tmp.exr";
  writeImage(png, OIIO::TypeDesc::UINT16, 1);
  writeImage(exr, OIIO::TypeDesc::HALF, 3);
  writeFile(out / "load_dem" / "image.png", std::string("\x03", 1) + readFile(png));
  writeFile(out / "load_dem" / "image.exr", std::string("\x04", 1) + readFile(exr));
  fs::remove(png);
  fs::remove(exr);
  std::printf("fuzz_seeds: wrote seeds to %s\n", out.c_str());
  return 0;
}
