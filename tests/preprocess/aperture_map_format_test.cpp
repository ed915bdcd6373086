// The aperture map's file format is the one an OpenImageIO write gives, though
// terrain/io/aperture_map.cpp uses OpenEXR directly: maps written by either
// read the same in both, and a broken file is an InputError.
#include <gtest/gtest.h>

#include <Imath/half.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "aperture/preprocess/bake.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/pixel_checksum.h"
#include "aperture/terrain/version.h"
#include "aperture/tests/preprocess/bake_test_util.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal {
namespace {

// 70 x 45: several ZIP chunks of 16 rows, the last one partial.
ApertureMap bakedMap() {
  const Heightfield field = test::makeField(
      70, 45, 30.0, [](double x, double y) { return 200 * std::sin(x / 300) * std::cos(y / 200); });
  BakeOptions options;
  options.azimuths = 16;
  ApertureMap map = bakeApertures(field, options).aperture;
  map.info.source = "wavy.tif";
  map.info.curvature = true;
  map.info.refraction = 0.13;
  map.info.maxDistanceM = 1500;
  map.info.edge = "clamp";
  return map;
}

// An aperture map written through OpenImageIO, as aperture's first writer did,
// plus the pixel checksum when one is given.
void writeWithOiio(const std::string& path, const ApertureMap& map, bool halfFloat,
                   const std::string& pixelChecksum = "") {
  OIIO::ImageSpec spec(map.width, map.height, 4,
                       halfFloat ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  spec.channelnames = {"R", "G", "B", "A"};
  spec.attribute("compression", "zip");
  const ApertureMapInfo& i = map.info;
  spec.attribute("aal:version", i.version);
  spec.attribute("aal:azimuths", i.azimuths);
  spec.attribute("aal:method", i.method);
  spec.attribute("aal:cellSizeX", static_cast<float>(i.cellSizeX));
  spec.attribute("aal:cellSizeY", static_cast<float>(i.cellSizeY));
  spec.attribute("aal:zScale", static_cast<float>(i.zScale));
  spec.attribute("aal:source", i.source);
  spec.attribute("aal:sourceSize",
                 std::to_string(i.sourceWidth) + "x" + std::to_string(i.sourceHeight));
  spec.attribute("aal:sourceChecksum", i.sourceChecksum);
  spec.attribute("aal:edge", i.edge);
  spec.attribute("aal:curvature", i.curvature ? 1 : 0);
  spec.attribute("aal:refraction", static_cast<float>(i.refraction));
  spec.attribute("aal:maxDistance", static_cast<float>(i.maxDistanceM));
  if (i.originCol != 0 || i.originRow != 0 || map.width != i.sourceWidth ||
      map.height != i.sourceHeight) {
    spec.attribute("aal:tileOrigin",
                   std::to_string(i.originCol) + "," + std::to_string(i.originRow));
  }
  spec.attribute("aal:software", softwareName());
  if (!pixelChecksum.empty()) spec.attribute("aal:pixelChecksum", pixelChecksum);
  auto out = OIIO::ImageOutput::create(path);
  ASSERT_TRUE(out && out->open(path, spec)) << OIIO::geterror();
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, map.texels.data())) << out->geterror();
  ASSERT_TRUE(out->close());
}

struct OiioImage {
  OIIO::ImageSpec spec;
  std::vector<unsigned char> pixels;  // as stored: halves or floats
};

OiioImage readWithOiio(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << OIIO::geterror();
  if (!in) return {};
  OiioImage image{in->spec(), {}};
  image.pixels.resize(image.spec.image_bytes());
  EXPECT_TRUE(in->read_image(0, 0, 0, 4, image.spec.format, image.pixels.data())) << in->geterror();
  return image;
}

std::string fileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Byte offset where a single-part EXR's header ends (after the null byte
// that closes its attribute list), and the attributes' names in file order.
size_t headerEnd(const std::string& file, std::vector<std::string>* names = nullptr) {
  size_t at = 8;  // magic number and version
  while (at < file.size() && file[at] != '\0') {
    const std::string name = file.c_str() + at;
    at += name.size() + 1;
    const std::string type = file.c_str() + at;
    at += type.size() + 1;
    int32_t size = 0;
    if (at + 4 > file.size()) break;
    std::memcpy(&size, file.data() + at, 4);
    at += 4 + static_cast<size_t>(size);
    if (names) names->push_back(name);
  }
  return at + 1;
}

// The header's attribute names, sorted.
std::vector<std::string> headerAttributes(const std::string& file) {
  std::vector<std::string> names;
  headerEnd(file, &names);
  std::sort(names.begin(), names.end());
  return names;
}

// The pixel chunks: what follows the header and the chunk offset table.
std::string chunkBytes(const std::string& file, int chunks) {
  const size_t start = headerEnd(file) + 8 * static_cast<size_t>(chunks);
  return start <= file.size() ? file.substr(start) : std::string();
}

void expectSameInfo(const ApertureMapInfo& a, const ApertureMapInfo& b) {
  EXPECT_EQ(a.version, b.version);
  EXPECT_EQ(a.azimuths, b.azimuths);
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(static_cast<float>(a.cellSizeX), static_cast<float>(b.cellSizeX));
  EXPECT_EQ(static_cast<float>(a.cellSizeY), static_cast<float>(b.cellSizeY));
  EXPECT_EQ(static_cast<float>(a.zScale), static_cast<float>(b.zScale));
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.sourceWidth, b.sourceWidth);
  EXPECT_EQ(a.sourceHeight, b.sourceHeight);
  EXPECT_EQ(a.sourceChecksum, b.sourceChecksum);
  EXPECT_EQ(a.edge, b.edge);
  EXPECT_EQ(a.curvature, b.curvature);
  EXPECT_EQ(static_cast<float>(a.refraction), static_cast<float>(b.refraction));
  EXPECT_EQ(static_cast<float>(a.maxDistanceM), static_cast<float>(b.maxDistanceM));
  EXPECT_EQ(a.originCol, b.originCol);
  EXPECT_EQ(a.originRow, b.originRow);
}

class ApertureMapFormat : public testing::TestWithParam<bool> {};

TEST_P(ApertureMapFormat, NewMapsReadInOiioAsTheOldOnes) {
  const bool halfFloat = GetParam();
  test::TempDir dir;
  ApertureMap map = bakedMap();
  const std::string fresh = (dir.path() / "new.exr").string();
  const std::string old = (dir.path() / "old.exr").string();
  writeApertureMap(fresh, map, halfFloat, MapCompression::Zip);
  const std::optional<uint64_t> checksum = ApertureMapReader(fresh).header().pixelChecksum;
  ASSERT_TRUE(checksum.has_value());
  EXPECT_EQ(ApertureMapReader(fresh).header().info.software, softwareName());
  writeWithOiio(old, map, halfFloat, checksumHex(*checksum));
  // The chunks are byte for byte OpenImageIO's (the same ZIP level, the same
  // rows per chunk); the header holds the same attributes (below), in the
  // order they were set rather than sorted, plus the optional `type`.
  const int zipChunks = (map.height + 15) / 16;
  EXPECT_EQ(chunkBytes(fileBytes(fresh), zipChunks), chunkBytes(fileBytes(old), zipChunks));
  std::vector<std::string> withType = headerAttributes(fileBytes(old));
  withType.push_back("type");
  std::sort(withType.begin(), withType.end());
  EXPECT_EQ(headerAttributes(fileBytes(fresh)), withType);

  const OiioImage a = readWithOiio(fresh), b = readWithOiio(old);
  EXPECT_EQ(a.spec.width, 70);
  EXPECT_EQ(a.spec.height, 45);
  EXPECT_EQ(a.spec.format, halfFloat ? OIIO::TypeDesc::HALF : OIIO::TypeDesc::FLOAT);
  EXPECT_EQ(a.spec.format, b.spec.format);
  EXPECT_EQ(a.spec.channelnames, b.spec.channelnames);
  EXPECT_EQ(a.spec.get_string_attribute("compression"), "zip");
  // Every attribute but the date: same name, type and value.
  EXPECT_EQ(a.spec.extra_attribs.size(), b.spec.extra_attribs.size());
  for (const OIIO::ParamValue& attribute : b.spec.extra_attribs) {
    if (attribute.name() == "DateTime") continue;
    const OIIO::ParamValue* same = a.spec.find_attribute(attribute.name());
    ASSERT_TRUE(same) << attribute.name();
    EXPECT_EQ(same->type(), attribute.type()) << attribute.name();
    EXPECT_EQ(same->get_string(), attribute.get_string()) << attribute.name();
  }
  EXPECT_TRUE(a.spec.find_attribute("DateTime"));
  EXPECT_EQ(a.spec.get_int_attribute("aal:curvature"), 1);
  EXPECT_EQ(a.spec.get_string_attribute("aal:edge"), "clamp");
  ASSERT_EQ(a.pixels.size(), b.pixels.size());
  EXPECT_EQ(std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size()), 0);
  if (halfFloat) {
    const auto* halves = reinterpret_cast<const Imath::half*>(a.pixels.data());
    for (size_t i = 0; i < map.texels.size(); ++i) {
      ASSERT_EQ(halves[i].bits(), Imath::half(map.texels[i]).bits()) << i;
    }
  } else {
    EXPECT_EQ(std::memcmp(a.pixels.data(), map.texels.data(), a.pixels.size()), 0);
  }
}

TEST_P(ApertureMapFormat, OldMapsReadAsInOiio) {
  const bool halfFloat = GetParam();
  test::TempDir dir;
  ApertureMap map = bakedMap();
  // A tile of a tiled bake: its place in the DEM in aal:tileOrigin.
  map.info.originCol = 64;
  map.info.originRow = 32;
  map.info.sourceWidth = 200;
  map.info.sourceHeight = 100;
  const std::string old = (dir.path() / "old.exr").string();
  writeWithOiio(old, map, halfFloat);

  const ApertureMap back = readApertureMap(old);
  EXPECT_EQ(back.width, 70);
  EXPECT_EQ(back.height, 45);
  expectSameInfo(back.info, map.info);
  std::vector<float> floats(map.texels.size());
  {
    auto in = OIIO::ImageInput::open(old);
    ASSERT_TRUE(in);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, floats.data()));
  }
  EXPECT_EQ(back.texels, floats);

  ApertureMapReader reader(old);
  EXPECT_EQ(reader.header().width, 70);
  expectSameInfo(reader.header().info, map.info);
  std::vector<uint16_t> halves(map.texels.size()), expected(map.texels.size());
  {
    auto in = OIIO::ImageInput::open(old);
    ASSERT_TRUE(in);
    ASSERT_TRUE(in->read_image(0, 0, 0, 4, OIIO::TypeDesc::HALF, expected.data()));
  }
  // Bands that start and end inside ZIP chunks.
  const size_t rowHalves = 70 * 4;
  for (int first = 0; first < 45; first += 7) {
    const int end = std::min(45, first + 7);
    reader.readHalfRows(first, end, halves.data() + first * rowHalves);
  }
  EXPECT_EQ(halves, expected);
}

INSTANTIATE_TEST_SUITE_P(HalfAndFloat, ApertureMapFormat, testing::Bool(),
                         [](const testing::TestParamInfo<bool>& p) {
                           return p.param ? "Half" : "Float";
                         });

// Cut anywhere (in the magic number, the header, the offset table, the
// pixels), a map is an InputError naming it, from readApertureMap and from
// ApertureMapReader, never a crash (AAL_SANITIZE=ON scripts/test.sh runs it
// under ASan).
TEST(ApertureMapFile, TruncatedAnywhereIsAnInputErrorNamingIt) {
  test::TempDir dir;
  const std::string good = (dir.path() / "good.exr").string();
  writeApertureMap(good, bakedMap(), true);
  const auto size = std::filesystem::file_size(good);
  std::vector<uintmax_t> cuts = {0, 2, 4, 100, 400};
  for (uintmax_t cut = 600; cut < size; cut += (size - 600) / 17) cuts.push_back(cut);
  cuts.push_back(size - 1);
  for (const uintmax_t cut : cuts) {
    SCOPED_TRACE("cut at " + std::to_string(cut) + " of " + std::to_string(size) + " bytes");
    const std::string path = (dir.path() / ("cut" + std::to_string(cut) + ".exr")).string();
    std::filesystem::copy_file(good, path);
    std::filesystem::resize_file(path, cut);
    try {
      readApertureMap(path);
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
    try {
      ApertureMapReader reader(path);
      const ApertureMapHeader& header = reader.header();
      std::vector<uint16_t> halves(static_cast<size_t>(header.width) * header.height * 4);
      reader.readHalfRows(0, header.height, halves.data());
      FAIL() << "no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

// SOURCE_DATE_EPOCH (reproducible-builds.org) fixes the capDate, in UTC:
// two writes of one map are then the same bytes (the MPI bake's tests
// compare folders so). Without it the capDate is the time of the write.
TEST(ApertureMapFile, SourceDateEpochFixesTheCaptureDate) {
  test::TempDir dir;
  const ApertureMap map = bakedMap();
  const auto bytes = [](const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  };
  ASSERT_EQ(setenv("SOURCE_DATE_EPOCH", "1700000000", 1), 0);
  writeApertureMap((dir.path() / "a.exr").string(), map, true);
  writeApertureMap((dir.path() / "b.exr").string(), map, true);
  unsetenv("SOURCE_DATE_EPOCH");
  const std::string a = bytes(dir.path() / "a.exr");
  EXPECT_NE(a.find("2023:11:14 22:13:20"), std::string::npos);
  EXPECT_TRUE(a == bytes(dir.path() / "b.exr"));
  writeApertureMap((dir.path() / "c.exr").string(), map, true);
  EXPECT_EQ(bytes(dir.path() / "c.exr").find("2023:11:14 22:13:20"), std::string::npos);
}

TEST(ApertureMapFile, ThreeChannelsAreAnInputError) {
  test::TempDir dir;
  const std::string path = (dir.path() / "rgb.exr").string();
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeDesc::HALF);
  spec.attribute("aal:version", 1);
  std::vector<float> pixels(48, 0.5f);
  ASSERT_TRUE(out->open(path, spec));
  ASSERT_TRUE(out->write_image(OIIO::TypeDesc::FLOAT, pixels.data()));
  out->close();
  try {
    readApertureMap(path);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("3 channels"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace aal
