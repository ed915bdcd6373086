#include "aperture_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>

#include <OpenImageIO/imageio.h>

#include "atomic_file.h"
#include "errors.h"

namespace aal {

float ApertureMap::visibleFraction(size_t texel) const {
  return 1.0f - std::cos(texels[4 * texel + 3]);
}

std::string heightfieldChecksum(const Heightfield& field) {
  uint64_t hash = 0xcbf29ce484222325ull;
  auto mix = [&hash](const void* data, size_t bytes) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < bytes; ++i) {
      hash ^= p[i];
      hash *= 0x100000001b3ull;
    }
  };
  mix(&field.width, sizeof field.width);
  mix(&field.height, sizeof field.height);
  mix(field.z.data(), field.z.size() * sizeof(float));
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash));
  return text;
}

void writeApertureMap(const std::string& path, const ApertureMap& map, bool halfFloat) {
  AtomicOutput output(path);
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

  auto out = OIIO::ImageOutput::create(output.temporaryPath().string());
  if (!out || !out->open(output.temporaryPath().string(), spec)) {
    throw std::runtime_error("cannot write aperture map " + path + ": " + OIIO::geterror());
  }
  // In blocks of rows, so that converting to half never copies the whole map.
  constexpr int kRows = 64;
  for (int y = 0; y < map.height; y += kRows) {
    const int end = std::min(map.height, y + kRows);
    const float* rows = map.texels.data() + static_cast<size_t>(y) * map.width * 4;
    if (!out->write_scanlines(y, end, 0, OIIO::TypeDesc::FLOAT, rows)) {
      throw std::runtime_error("cannot write aperture map " + path + ": " + out->geterror());
    }
  }
  if (!out->close()) {
    throw std::runtime_error("cannot write aperture map " + path + ": " + out->geterror());
  }
  output.commit();
}

namespace {

std::unique_ptr<OIIO::ImageInput> openApertureMap(const std::string& path,
                                                  ApertureMapHeader& header) {
  if (!std::filesystem::exists(path)) throw InputError("aperture map " + path + " does not exist");
  auto in = OIIO::ImageInput::open(path);
  if (!in) throw InputError("cannot read aperture map " + path + ": " + OIIO::geterror());
  const OIIO::ImageSpec& spec = in->spec();
  if (spec.nchannels != 4) {
    throw InputError("aperture map " + path + " has " + std::to_string(spec.nchannels) +
                     " channels, expected 4 (bent normal RGB + arc length A)");
  }
  if (!spec.find_attribute("aal:version")) {
    throw InputError("aperture map " + path + " has no aal: attributes: not made by aal-bake");
  }
  header.width = spec.width;
  header.height = spec.height;
  ApertureMapInfo& i = header.info;
  i.version = spec.get_int_attribute("aal:version");
  i.azimuths = spec.get_int_attribute("aal:azimuths");
  i.method = spec.get_string_attribute("aal:method");
  i.cellSizeX = spec.get_float_attribute("aal:cellSizeX");
  i.cellSizeY = spec.get_float_attribute("aal:cellSizeY");
  i.zScale = spec.get_float_attribute("aal:zScale", 1.0f);
  i.source = spec.get_string_attribute("aal:source");
  i.sourceChecksum = spec.get_string_attribute("aal:sourceChecksum");
  i.edge = spec.get_string_attribute("aal:edge", "open");
  i.curvature = spec.get_int_attribute("aal:curvature") != 0;
  i.refraction = spec.get_float_attribute("aal:refraction");
  i.maxDistanceM = spec.get_float_attribute("aal:maxDistance");
  if (std::sscanf(spec.get_string_attribute("aal:sourceSize").c_str(), "%dx%d", &i.sourceWidth,
                  &i.sourceHeight) != 2) {
    throw InputError("aperture map " + path + " has a malformed aal:sourceSize attribute");
  }
  if (const std::string origin = spec.get_string_attribute("aal:tileOrigin"); !origin.empty()) {
    if (std::sscanf(origin.c_str(), "%d,%d", &i.originCol, &i.originRow) != 2) {
      throw InputError("aperture map " + path + " has a malformed aal:tileOrigin attribute");
    }
  }
  return in;
}

bool isFolder(const std::string& path) {
  std::error_code ignored;
  return std::filesystem::is_directory(path, ignored);
}

std::string tilePath(const std::string& folder, int row, int column) {
  return (std::filesystem::path(folder) / apertureTileName(row, column)).string();
}

// Opens tile (row, column) of a tiled map and checks it belongs there.
std::unique_ptr<OIIO::ImageInput> openApertureTile(const ApertureTileIndex& index,
                                                   const std::string& folder, int row, int column) {
  const std::string path = tilePath(folder, row, column);
  ApertureMapHeader header;
  auto in = openApertureMap(path, header);
  checkApertureTile(index, row, column, header, path);
  return in;
}

void throwUnreadable(const std::string& path, const std::string& error) {
  throw InputError("cannot read aperture map " + path + " (truncated or corrupt): " + error);
}

// Every tile of a tiled map into one map of floats.
ApertureMap readTiledApertureMap(const std::string& folder) {
  const ApertureTileIndex index = readApertureTileIndex(folder);
  ApertureMap map;
  map.width = index.map.width;
  map.height = index.map.height;
  map.info = index.map.info;
  map.texels.resize(map.texelCount() * 4);
  const OIIO::stride_t rowBytes = static_cast<OIIO::stride_t>(map.width) * 4 * sizeof(float);
  for (int row = 0; row < index.rows(); ++row) {
    for (int column = 0; column < index.columns(); ++column) {
      auto in = openApertureTile(index, folder, row, column);
      float* corner = map.texels.data() + (static_cast<size_t>(row) * index.tileSize * map.width +
                                           static_cast<size_t>(column) * index.tileSize) *
                                              4;
      if (!in->read_scanlines(0, 0, 0, index.tileHeight(row), 0, 0, 4, OIIO::TypeDesc::FLOAT,
                              corner, 4 * sizeof(float), rowBytes) ||
          in->has_error()) {
        throwUnreadable(tilePath(folder, row, column), in->geterror());
      }
    }
  }
  return map;
}

}  // namespace

std::string apertureTileName(int row, int column) {
  char name[64];
  std::snprintf(name, sizeof name, "tile_%04d_%04d.exr", row, column);
  return name;
}

namespace {

constexpr const char* kIndexName = "index.txt";
constexpr const char* kIndexMagic = "aal-aperture-tiles 1";

}  // namespace

void writeApertureTileIndex(const std::string& folder, const ApertureTileIndex& index) {
  const std::filesystem::path path = std::filesystem::path(folder) / kIndexName;
  AtomicOutput output(path);
  std::ostringstream text;
  text.precision(17);
  const ApertureMapInfo& i = index.map.info;
  text << kIndexMagic << "\n"
       << "width " << index.map.width << "\n"
       << "height " << index.map.height << "\n"
       << "tile-size " << index.tileSize << "\n"
       << "tiles " << index.columns() << "x" << index.rows() << "\n"
       << "version " << i.version << "\n"
       << "azimuths " << i.azimuths << "\n"
       << "method " << i.method << "\n"
       << "cell-size-x " << i.cellSizeX << "\n"
       << "cell-size-y " << i.cellSizeY << "\n"
       << "z-scale " << i.zScale << "\n"
       << "source-checksum " << i.sourceChecksum << "\n"
       << "edge " << i.edge << "\n"
       << "curvature " << (i.curvature ? 1 : 0) << "\n"
       << "refraction " << i.refraction << "\n"
       << "max-distance " << i.maxDistanceM << "\n"
       << "source " << i.source << "\n";
  std::ofstream out(output.temporaryPath());
  out << text.str();
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
  output.commit();
}

ApertureTileIndex readApertureTileIndex(const std::string& folder) {
  const std::filesystem::path path = std::filesystem::path(folder) / kIndexName;
  std::ifstream in(path);
  if (!in) {
    throw InputError("aperture map folder " + folder + " has no " + kIndexName +
                     ": not a tiled bake, or its bake has not finished (run the same aal-bake "
                     "command again to resume it)");
  }
  std::map<std::string, std::string> values;
  std::string line;
  std::getline(in, line);
  if (line != kIndexMagic) {
    throw InputError(path.string() + " is not an aperture tile index (first line '" + line + "')");
  }
  while (std::getline(in, line)) {
    const size_t space = line.find(' ');
    if (space != std::string::npos) values[line.substr(0, space)] = line.substr(space + 1);
  }
  auto text = [&](const char* key) -> const std::string& {
    const auto found = values.find(key);
    if (found == values.end()) {
      throw InputError(path.string() + " lacks '" + key + "': truncated or not an index");
    }
    return found->second;
  };
  auto number = [&](const char* key) {
    const std::string& value = text(key);
    char* end = nullptr;
    const double x = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || *end != '\0' || !std::isfinite(x)) {
      throw InputError(path.string() + ": '" + key + "' is not a number: '" + value + "'");
    }
    return x;
  };
  auto integer = [&](const char* key, int smallest) {
    const double x = number(key);
    if (x != std::floor(x) || x < smallest || x > 1 << 30) {
      throw InputError(path.string() + ": '" + key +
                       "' must be an integer >= " + std::to_string(smallest));
    }
    return static_cast<int>(x);
  };
  ApertureTileIndex index;
  index.map.width = integer("width", 1);
  index.map.height = integer("height", 1);
  index.tileSize = integer("tile-size", 1);
  ApertureMapInfo& i = index.map.info;
  i.version = integer("version", 1);
  i.azimuths = integer("azimuths", 0);
  i.method = text("method");
  i.cellSizeX = number("cell-size-x");
  i.cellSizeY = number("cell-size-y");
  i.zScale = number("z-scale");
  i.sourceChecksum = text("source-checksum");
  i.edge = text("edge");
  i.curvature = integer("curvature", 0) != 0;
  i.refraction = number("refraction");
  i.maxDistanceM = number("max-distance");
  i.source = text("source");
  i.sourceWidth = index.map.width;
  i.sourceHeight = index.map.height;
  return index;
}

void checkApertureTile(const ApertureTileIndex& index, int row, int column,
                       const ApertureMapHeader& tile, const std::string& tilePath) {
  const ApertureMapInfo &want = index.map.info, &got = tile.info;
  auto same = [](double a, double b) { return static_cast<float>(a) == static_cast<float>(b); };
  std::string differs;
  if (tile.width != index.tileWidth(column) || tile.height != index.tileHeight(row) ||
      got.originCol != column * index.tileSize || got.originRow != row * index.tileSize) {
    differs = "its size or place in the DEM";
  } else if (got.sourceWidth != index.map.width || got.sourceHeight != index.map.height ||
             got.sourceChecksum != want.sourceChecksum) {
    differs = "the DEM it was baked from";
  } else if (got.azimuths != want.azimuths || got.method != want.method || got.edge != want.edge ||
             got.curvature != want.curvature || !same(got.refraction, want.refraction) ||
             !same(got.maxDistanceM, want.maxDistanceM) || !same(got.cellSizeX, want.cellSizeX) ||
             !same(got.cellSizeY, want.cellSizeY) || !same(got.zScale, want.zScale)) {
    differs = "the bake options";
  }
  if (!differs.empty()) {
    throw InputError("aperture tile " + tilePath +
                     " does not belong to this tiled map: " + differs + " differ");
  }
}

ApertureMap readApertureMap(const std::string& path) {
  if (isFolder(path)) return readTiledApertureMap(path);
  ApertureMapHeader header;
  auto in = openApertureMap(path, header);
  ApertureMap map;
  map.width = header.width;
  map.height = header.height;
  map.info = header.info;
  map.texels.resize(map.texelCount() * 4);
  if (!in->read_image(0, 0, 0, 4, OIIO::TypeDesc::FLOAT, map.texels.data())) {
    throw InputError("cannot read aperture map " + path +
                     " (truncated or corrupt): " + in->geterror());
  }
  return map;
}

struct ApertureMapReader::Impl {
  std::unique_ptr<OIIO::ImageInput> input;  // a single file
  // A tiled map: its index and the open tiles of one row of tiles.
  std::optional<ApertureTileIndex> tiles;
  int openTileRow = -1;
  std::vector<std::unique_ptr<OIIO::ImageInput>> rowTiles;

  void readTiledRows(const std::string& folder, int firstRow, int endRow, void* destination) {
    const ApertureTileIndex& index = *tiles;
    const OIIO::stride_t texelBytes = 4 * sizeof(uint16_t);
    const OIIO::stride_t rowBytes = texelBytes * index.map.width;
    for (int row = firstRow; row < endRow;) {
      const int tileRow = row / index.tileSize;
      const int top = tileRow * index.tileSize;
      const int bandEnd = std::min(endRow, top + index.tileSize);
      if (tileRow != openTileRow) {
        rowTiles.clear();
        openTileRow = -1;
        for (int column = 0; column < index.columns(); ++column) {
          rowTiles.push_back(openApertureTile(index, folder, tileRow, column));
        }
        openTileRow = tileRow;
      }
      for (int column = 0; column < index.columns(); ++column) {
        OIIO::ImageInput& in = *rowTiles[static_cast<size_t>(column)];
        char* corner = static_cast<char*>(destination) + (row - firstRow) * rowBytes +
                       static_cast<OIIO::stride_t>(column) * index.tileSize * texelBytes;
        if (!in.read_scanlines(0, 0, row - top, bandEnd - top, 0, 0, 4, OIIO::TypeDesc::HALF,
                               corner, texelBytes, rowBytes) ||
            in.has_error()) {
          throwUnreadable(tilePath(folder, tileRow, column), in.geterror());
        }
      }
      row = bandEnd;
    }
  }
};

ApertureMapReader::ApertureMapReader(const std::string& path) : path_(path), impl_(new Impl) {
  try {
    if (isFolder(path)) {
      impl_->tiles = readApertureTileIndex(path);
      header_ = impl_->tiles->map;
    } else {
      impl_->input = openApertureMap(path, header_);
    }
  } catch (...) {
    delete impl_;
    throw;
  }
}

ApertureMapReader::~ApertureMapReader() {
  delete impl_;
}

void ApertureMapReader::readHalfRows(int firstRow, int endRow, void* destination) {
  if (firstRow < 0 || endRow > header_.height || firstRow > endRow) {
    throw std::out_of_range("aperture map rows out of range");
  }
  if (impl_->tiles) {
    impl_->readTiledRows(path_, firstRow, endRow, destination);
    return;
  }
  if (!impl_->input->read_scanlines(0, 0, firstRow, endRow, 0, 0, 4, OIIO::TypeDesc::HALF,
                                    destination) ||
      impl_->input->has_error()) {
    throw InputError("cannot read aperture map " + path_ +
                     " (truncated or corrupt): " + impl_->input->geterror());
  }
}

void checkApertureMatchesDem(const ApertureMapHeader& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath) {
  const std::string pair = "aperture map " + mapPath + " does not belong to DEM " + demPath;
  if (map.width != field.width || map.height != field.height) {
    throw InputError(pair + ": map is " + std::to_string(map.width) + "x" +
                     std::to_string(map.height) + ", DEM is " + std::to_string(field.width) + "x" +
                     std::to_string(field.height));
  }
  if (map.info.sourceChecksum != heightfieldChecksum(field)) {
    throw InputError(pair + ": it was baked from other heights (" + map.info.source +
                     "); bake it again with aal-bake");
  }
}

void checkApertureMatchesDem(const ApertureMap& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath) {
  checkApertureMatchesDem(ApertureMapHeader{map.width, map.height, map.info}, mapPath, field,
                          demPath);
}

}  // namespace aal
