#include "aperture/terrain/io/aperture_map.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>

#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfConvert.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfThreading.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/aperture_geotiff.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/exr_scanline_writer.h"
#include "aperture/terrain/io/half_floats.h"
#include "aperture/terrain/io/heightfield_checksum.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/io/pixel_checksum.h"
#include "aperture/terrain/version.h"

namespace aal {

float ApertureMap::visibleFraction(size_t texel) const {
  return 1.0f - std::cos(texels[4 * texel + 3]);
}

namespace {

// The file format is the one OpenImageIO wrote before this file used OpenEXR
// directly (docs/baking.md): scanlines, ZIP, channels R, G, B, A of halves or
// floats, int, float and string `aal:` attributes and a capture date.
constexpr const char* kChannels[4] = {"R", "G", "B", "A"};

// OpenEXR compresses and decompresses the chunks of a file in parallel on its
// global thread pool, which is empty until it is given a size.
void useEveryCoreForExr() {
  static std::once_flag once;
  std::call_once(once, [] {
    Imf::setGlobalThreadCount(static_cast<int>(std::max(1u, std::thread::hardware_concurrency())));
  });
}

// "YYYY:MM:DD HH:MM:SS", local time: the capDate OpenImageIO wrote. With
// SOURCE_DATE_EPOCH set (seconds since 1970, the reproducible-builds.org
// convention) that time in UTC instead, so that two bakes of the same DEM
// (aal-bake's tiles and aal-bake-mpi's, say) are the same files byte for
// byte.
std::string captureDate() {
  std::time_t when = std::time(nullptr);
  std::tm calendar{};
  const char* epoch = std::getenv("SOURCE_DATE_EPOCH");
  char* end = nullptr;
  const long long fixed = epoch ? std::strtoll(epoch, &end, 10) : -1;
  if (epoch && *epoch && end && *end == '\0' && fixed >= 0) {
    when = static_cast<std::time_t>(fixed);
    gmtime_r(&when, &calendar);
  } else {
    localtime_r(&when, &calendar);
  }
  char text[32];
  std::strftime(text, sizeof text, "%Y:%m:%d %H:%M:%S", &calendar);
  return text;
}

// A frame buffer that puts rows [firstRow, endRow) of the file's data window
// at `destination`, as `type` components, texels `texelBytes` and rows
// `rowBytes` apart (the channels in R, G, B, A order within a texel).
Imf::FrameBuffer rowsFrameBuffer(const Imath::Box2i& dataWindow, int firstRow, int endRow,
                                 Imf::PixelType type, const void* destination, size_t texelBytes,
                                 size_t rowBytes) {
  const size_t componentBytes = type == Imf::HALF ? 2 : 4;
  const int width = dataWindow.max.x - dataWindow.min.x + 1;
  const Imath::V2i origin(dataWindow.min.x, dataWindow.min.y + firstRow);
  Imf::FrameBuffer frame;
  for (int c = 0; c < 4; ++c) {
    frame.insert(kChannels[c],
                 Imf::Slice::Make(type, static_cast<const char*>(destination) + c * componentBytes,
                                  origin, width, endRow - firstRow, texelBytes, rowBytes));
  }
  return frame;
}

// Rows converted or checked a block at a time, so that a map is never
// copied whole; a block is 16 of the ZIP chunks (16 rows each) OpenEXR's
// thread pool compresses or decodes in parallel.
constexpr int kBlockRows = 256;

// aal:pixelChecksum of the map as writeApertureMap stores it. OpenEXR writes
// the header before the pixels, so this is a pass of its own.
uint64_t storedPixelChecksum(const ApertureMap& map, bool halfFloat) {
  const size_t rowFloats = static_cast<size_t>(map.width) * 4;
  std::vector<uint64_t> hashes(static_cast<size_t>(map.height));
  tbb::parallel_for(tbb::blocked_range<int>(0, map.height), [&](const tbb::blocked_range<int>& r) {
    std::vector<uint16_t> halves(halfFloat ? rowFloats : 0);
    for (int y = r.begin(); y < r.end(); ++y) {
      const float* row = map.texels.data() + static_cast<size_t>(y) * rowFloats;
      if (halfFloat) {
        floatsToHalves(row, halves.data(), rowFloats);  // as the writer converts
        hashes[static_cast<size_t>(y)] =
            PixelChecksum::rowHash(y, halves.data(), rowFloats * sizeof(uint16_t));
      } else {
        hashes[static_cast<size_t>(y)] = PixelChecksum::rowHash(y, row, rowFloats * sizeof(float));
      }
    }
  });
  PixelChecksum sum(map.height);
  for (int y = 0; y < map.height; ++y) sum.addRowHash(y, hashes[static_cast<size_t>(y)]);
  return sum.value();
}

}  // namespace

void writeApertureMap(const std::string& path, const ApertureMap& map, bool halfFloat,
                      MapCompression compression) {
  AtomicOutput output(path);
  const std::string temporary = output.temporaryPath().string();
  try {
    if (map.texels.size() != map.texelCount() * 4) {
      throw std::invalid_argument("the map has " + std::to_string(map.texels.size()) +
                                  " floats, not 4 per texel");
    }
    const ApertureMapInfo& i = map.info;
    std::vector<ExrAttribute> attributes = {
        {"aal:version", i.version},
        {"aal:azimuths", i.azimuths},
        {"aal:method", i.method},
        {"aal:cellSizeX", static_cast<float>(i.cellSizeX)},
        {"aal:cellSizeY", static_cast<float>(i.cellSizeY)},
        {"aal:zScale", static_cast<float>(i.zScale)},
        {"aal:source", i.source},
        {"aal:sourceSize", std::to_string(i.sourceWidth) + "x" + std::to_string(i.sourceHeight)},
        {"aal:sourceChecksum", i.sourceChecksum},
        {"aal:edge", i.edge},
        {"aal:curvature", i.curvature ? 1 : 0},
        {"aal:refraction", static_cast<float>(i.refraction)},
        {"aal:maxDistance", static_cast<float>(i.maxDistanceM)},
    };
    if (i.originCol != 0 || i.originRow != 0 || map.width != i.sourceWidth ||
        map.height != i.sourceHeight) {
      attributes.push_back(
          {"aal:tileOrigin", std::to_string(i.originCol) + "," + std::to_string(i.originRow)});
    }
    attributes.push_back({"capDate", captureDate()});
    attributes.push_back({"aal:software", softwareName()});
    attributes.push_back({"aal:pixelChecksum", checksumHex(storedPixelChecksum(map, halfFloat))});
    ExrScanlineWriter file(temporary, map.width, map.height,
                           {kChannels[0], kChannels[1], kChannels[2], kChannels[3]}, halfFloat,
                           compression, attributes);
    // Blocks of rows, so that an interrupt is seen within ~0.1 s even at
    // 16384 columns; the writer converts to halves as it packs.
    const size_t rowFloats = static_cast<size_t>(map.width) * 4;
    for (int y = 0; y < map.height; y += kBlockRows) {
      const int end = std::min(map.height, y + kBlockRows);
      file.writeRows(map.texels.data() + static_cast<size_t>(y) * rowFloats, y, end);
      throwIfInterrupted();
    }
    file.finish();
  } catch (const Interrupted&) {
    throw;
  } catch (const std::exception& e) {
    throw output.failure(e.what(), "aperture map");
  }
  output.commit();
}

namespace {

int intAttribute(const Imf::Header& header, const char* name, int fallback) {
  const auto* a = header.findTypedAttribute<Imf::IntAttribute>(name);
  return a ? a->value() : fallback;
}

double floatAttribute(const Imf::Header& header, const char* name, double fallback) {
  if (const auto* a = header.findTypedAttribute<Imf::FloatAttribute>(name)) return a->value();
  if (const auto* a = header.findTypedAttribute<Imf::DoubleAttribute>(name)) return a->value();
  return fallback;
}

std::string stringAttribute(const Imf::Header& header, const char* name,
                            const std::string& fallback = "") {
  const auto* a = header.findTypedAttribute<Imf::StringAttribute>(name);
  return a ? a->value() : fallback;
}

void throwUnreadable(const std::string& path, const std::string& error) {
  throw InputError("cannot read aperture map " + path + " (truncated or corrupt): " + error);
}

size_t componentBytes(Imf::PixelType type) {
  return type == Imf::HALF ? sizeof(Imath::half) : sizeof(float);
}

// An open map file, and the checksum of the rows read from it so far.
struct OpenMap {
  std::unique_ptr<Imf::InputFile> file;
  std::string path;
  int width = 0, height = 0;
  Imf::PixelType stored = Imf::HALF;  // the four channels' type, when checked
  std::optional<uint64_t> expected;   // aal:pixelChecksum
  std::optional<PixelChecksum> sum;   // with `expected`
};

OpenMap openApertureMap(const std::string& path, ApertureMapHeader& header) {
  // Looked at before OpenEXR opens it: a FIFO would block the open forever.
  if (requireFileOrFolder(path, "aperture map " + path) == InputKind::Missing) {
    throw InputError("aperture map " + path + " does not exist");
  }
  useEveryCoreForExr();
  OpenMap map;
  map.path = path;
  try {
    map.file = std::make_unique<Imf::InputFile>(path.c_str());
  } catch (const std::exception& e) {
    throw InputError("cannot read aperture map " + path + ": " + e.what());
  }
  const Imf::Header& exr = map.file->header();
  std::string channels;
  int channelCount = 0;
  for (auto c = exr.channels().begin(); c != exr.channels().end(); ++c, ++channelCount) {
    channels += (channels.empty() ? "" : ", ") + std::string(c.name());
  }
  if (channelCount != 4) {
    throw InputError("aperture map " + path + " has " + std::to_string(channelCount) +
                     " channels, expected 4 (bent normal RGB + arc length A)");
  }
  for (const char* name : kChannels) {
    if (!exr.channels().findChannel(name)) {
      throw InputError("aperture map " + path + " has channels " + channels +
                       ", expected R, G, B (bent normal) and A (arc length)");
    }
  }
  if (exr.find("aal:version") == exr.end()) {
    throw InputError("aperture map " + path + " has no aal: attributes: not made by aal-bake");
  }
  const Imath::Box2i& window = exr.dataWindow();
  header.width = window.max.x - window.min.x + 1;
  header.height = window.max.y - window.min.y + 1;
  ApertureMapInfo& i = header.info;
  i.version = intAttribute(exr, "aal:version", 0);
  i.azimuths = intAttribute(exr, "aal:azimuths", 0);
  i.method = stringAttribute(exr, "aal:method");
  i.cellSizeX = floatAttribute(exr, "aal:cellSizeX", 0);
  i.cellSizeY = floatAttribute(exr, "aal:cellSizeY", 0);
  i.zScale = floatAttribute(exr, "aal:zScale", 1);
  i.source = stringAttribute(exr, "aal:source");
  i.sourceChecksum = stringAttribute(exr, "aal:sourceChecksum");
  i.software = stringAttribute(exr, "aal:software");
  i.edge = stringAttribute(exr, "aal:edge", "open");
  i.curvature = intAttribute(exr, "aal:curvature", 0) != 0;
  i.refraction = floatAttribute(exr, "aal:refraction", 0);
  i.maxDistanceM = floatAttribute(exr, "aal:maxDistance", 0);
  if (std::sscanf(stringAttribute(exr, "aal:sourceSize").c_str(), "%dx%d", &i.sourceWidth,
                  &i.sourceHeight) != 2) {
    throw InputError("aperture map " + path + " has a malformed aal:sourceSize attribute");
  }
  if (const std::string origin = stringAttribute(exr, "aal:tileOrigin"); !origin.empty()) {
    if (std::sscanf(origin.c_str(), "%d,%d", &i.originCol, &i.originRow) != 2) {
      throw InputError("aperture map " + path + " has a malformed aal:tileOrigin attribute");
    }
  }
  map.width = header.width;
  map.height = header.height;
  map.stored = exr.channels().findChannel("R")->type;
  if (exr.find("aal:pixelChecksum") != exr.end()) {
    header.pixelChecksum = parseChecksumHex(stringAttribute(exr, "aal:pixelChecksum"));
    if (!header.pixelChecksum) {
      throw InputError("aperture map " + path + " has a malformed aal:pixelChecksum attribute");
    }
    // The checksum is of the bytes writeApertureMap stores: four channels
    // of halves, or of floats.
    for (const char* name : kChannels) {
      const Imf::PixelType type = exr.channels().findChannel(name)->type;
      if (type != map.stored || type == Imf::UINT) {
        throw InputError("aperture map " + path +
                         " has an aal:pixelChecksum but not four channels of halves or of "
                         "floats: not written by aal-bake");
      }
    }
    map.expected = header.pixelChecksum;
    map.sum.emplace(header.height);
  }
  return map;
}

// Decodes rows [firstRow, endRow) of an open map (counted from the top of
// its data window) as `type` into `destination`, interleaved RGBA texels,
// rows `rowBytes` apart.
void decodeRows(OpenMap& map, int firstRow, int endRow, Imf::PixelType type, void* destination,
                size_t rowBytes) {
  try {
    const Imath::Box2i& window = map.file->header().dataWindow();
    map.file->setFrameBuffer(rowsFrameBuffer(window, firstRow, endRow, type, destination,
                                             4 * componentBytes(type), rowBytes));
    map.file->readPixels(window.min.y + firstRow, window.min.y + endRow - 1);
  } catch (const std::exception& e) {
    throwUnreadable(map.path, e.what());
  }
}

// Adds decoded rows [firstRow, endRow), in the file's own type and
// `rowBytes` apart, to the map's checksum, calling `convert(row)` (when
// given) on each once it is hashed: on all cores, in one pass over the rows
// while they are in the CPU's caches.
void addRows(OpenMap& map, int firstRow, int endRow, const void* rows, size_t rowBytes,
             const std::function<void(int)>& convert = {}) {
  const size_t bytes = static_cast<size_t>(map.width) * 4 * componentBytes(map.stored);
  std::vector<uint64_t> hashes(static_cast<size_t>(endRow - firstRow));
  tbb::parallel_for(firstRow, endRow, [&](int y) {
    const size_t i = static_cast<size_t>(y - firstRow);
    hashes[i] = PixelChecksum::rowHash(y, static_cast<const char*>(rows) + i * rowBytes, bytes);
    if (convert) convert(y);
  });
  for (int y = firstRow; y < endRow; ++y) {
    map.sum->addRowHash(y, hashes[static_cast<size_t>(y - firstRow)]);
  }
}

// Rows [firstRow, endRow) of an open map as `type` into `destination` (see
// decodeRows), checked against aal:pixelChecksum once every row has been read.
void readRows(OpenMap& map, int firstRow, int endRow, Imf::PixelType type, void* destination,
              size_t rowBytes) {
  if (firstRow == endRow) return;
  if (!map.sum || type == map.stored) {
    decodeRows(map, firstRow, endRow, type, destination, rowBytes);
    if (map.sum) addRows(map, firstRow, endRow, destination, rowBytes);
  } else {
    // The checksum is of the stored values: decode those, then convert as
    // OpenEXR does (Imf::floatToHalf; halves widen exactly).
    const size_t texels = static_cast<size_t>(map.width) * 4;
    const size_t storedRowBytes = texels * componentBytes(map.stored);
    const int blockRows = std::min(endRow - firstRow, kBlockRows);
    std::vector<char> block(storedRowBytes * static_cast<size_t>(blockRows));
    for (int y = firstRow; y < endRow; y += blockRows) {
      const int end = std::min(endRow, y + blockRows);
      decodeRows(map, y, end, map.stored, block.data(), storedRowBytes);
      addRows(map, y, end, block.data(), storedRowBytes, [&](int row) {
        const char* from = block.data() + static_cast<size_t>(row - y) * storedRowBytes;
        char* to = static_cast<char*>(destination) + static_cast<size_t>(row - firstRow) * rowBytes;
        if (type == Imf::FLOAT) {
          const auto* halves = reinterpret_cast<const Imath::half*>(from);
          std::copy(halves, halves + texels, reinterpret_cast<float*>(to));
        } else {
          const auto* floats = reinterpret_cast<const float*>(from);
          std::transform(floats, floats + texels, reinterpret_cast<Imath::half*>(to),
                         Imf::floatToHalf);
        }
      });
    }
  }
  if (map.sum && map.sum->complete() && map.sum->value() != *map.expected) {
    throw InputError("aperture map " + map.path +
                     " is corrupt: its pixels do not match the checksum in its header "
                     "(aal:pixelChecksum " +
                     checksumHex(*map.expected) + ", pixels " + checksumHex(map.sum->value()) +
                     "); bake it again with aal-bake");
  }
}

bool isFolder(const std::string& path) {
  std::error_code ignored;
  return std::filesystem::is_directory(path, ignored);
}

std::string tilePath(const std::string& folder, int row, int column) {
  return (std::filesystem::path(folder) / apertureTileName(row, column)).string();
}

// Opens tile (row, column) of a tiled map and checks it belongs there.
OpenMap openApertureTile(const ApertureTileIndex& index, const std::string& folder, int row,
                         int column) {
  const std::string path = tilePath(folder, row, column);
  ApertureMapHeader header;
  OpenMap tile = openApertureMap(path, header);
  checkApertureTile(index, row, column, header, path);
  return tile;
}

// Every tile of a tiled map into one map of floats.
ApertureMap readTiledApertureMap(const std::string& folder) {
  const ApertureTileIndex index = readApertureTileIndex(folder);
  ApertureMap map;
  map.width = index.map.width;
  map.height = index.map.height;
  map.info = index.map.info;
  map.texels.resize(map.texelCount() * 4);
  const size_t rowBytes = static_cast<size_t>(map.width) * 4 * sizeof(float);
  for (int row = 0; row < index.rows(); ++row) {
    for (int column = 0; column < index.columns(); ++column) {
      OpenMap tile = openApertureTile(index, folder, row, column);
      float* corner = map.texels.data() + (static_cast<size_t>(row) * index.tileSize * map.width +
                                           static_cast<size_t>(column) * index.tileSize) *
                                              4;
      readRows(tile, 0, index.tileHeight(row), Imf::FLOAT, corner, rowBytes);
    }
  }
  return map;
}

// A GeoTIFF map whole, as floats.
ApertureMap readApertureGeoTiff(const std::string& path) {
  ApertureMapHeader header;
  ApertureGeoTiff file(path, header);
  ApertureMap map;
  map.width = header.width;
  map.height = header.height;
  map.info = header.info;
  map.texels.resize(map.texelCount() * 4);
  const size_t rowBytes = static_cast<size_t>(map.width) * 4 * sizeof(float);
  for (int y = 0; y < map.height; y += kBlockRows) {
    const int end = std::min(map.height, y + kBlockRows);
    file.readFloatRows(y, end, map.texels.data() + static_cast<size_t>(y) * map.width * 4,
                       rowBytes);
    throwIfInterrupted();
  }
  return map;
}

// Rows of a GeoTIFF map as halves (8 bytes per texel, tightly packed),
// through floats a block at a time.
void readGeoTiffHalfRows(ApertureGeoTiff& file, int width, int firstRow, int endRow,
                         void* destination) {
  const size_t rowFloats = static_cast<size_t>(width) * 4;
  std::vector<float> block(rowFloats *
                           static_cast<size_t>(std::min(endRow - firstRow, kBlockRows)));
  for (int y = firstRow; y < endRow; y += kBlockRows) {
    const int end = std::min(endRow, y + kBlockRows);
    file.readFloatRows(y, end, block.data(), rowFloats * sizeof(float));
    floatsToHalves(
        block.data(),
        static_cast<uint16_t*>(destination) + static_cast<size_t>(y - firstRow) * rowFloats,
        rowFloats * static_cast<size_t>(end - y));
  }
}

}  // namespace

std::string apertureTileName(int row, int column) {
  char name[64];
  std::snprintf(name, sizeof name, "tile_%04d_%04d.exr", row, column);
  return name;
}

namespace {

std::string formatMetres(double metres) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", metres);
  return text;
}

constexpr const char* kIndexMagic = "aal-aperture-tiles 1";

}  // namespace

void writeApertureTileIndex(const std::string& folder, const ApertureTileIndex& index,
                            const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(folder) / name;
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
       << "sky-view-factor " << (index.skyViewFactor ? 1 : 0) << "\n"
       << "software " << softwareName() << "\n"
       << "source " << i.source << "\n";
  std::ofstream out(output.temporaryPath());
  out << text.str();
  out.close();
  if (!out) throw output.failure(std::strerror(errno));
  output.commit();
}

ApertureTileIndex readApertureTileIndex(const std::string& folder, const std::string& name) {
  const std::filesystem::path path = std::filesystem::path(folder) / name;
  requireFileOrFolder(path.string(), path.string());  // a FIFO would block the read
  std::ifstream in(path);
  if (!in) {
    throw InputError("aperture map folder " + folder + " has no " + name +
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
  if (const auto software = values.find("software"); software != values.end()) {
    i.software = software->second;
  }
  index.skyViewFactor = values.count("sky-view-factor") && integer("sky-view-factor", 0) != 0;
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
  if (isGeoTiffPath(path)) return readApertureGeoTiff(path);
  ApertureMapHeader header;
  OpenMap file = openApertureMap(path, header);
  ApertureMap map;
  map.width = header.width;
  map.height = header.height;
  map.info = header.info;
  map.texels.resize(map.texelCount() * 4);
  readRows(file, 0, map.height, Imf::FLOAT, map.texels.data(),
           static_cast<size_t>(map.width) * 4 * sizeof(float));
  return map;
}

struct ApertureMapReader::Impl {
  std::optional<OpenMap> input;            // a single EXR file
  std::optional<ApertureGeoTiff> geotiff;  // a single GeoTIFF
  // A tiled map: its index and the open tiles of one row of tiles.
  std::optional<ApertureTileIndex> tiles;
  int openTileRow = -1;
  std::vector<OpenMap> rowTiles;

  void readTiledRows(const std::string& folder, int firstRow, int endRow, void* destination) {
    const ApertureTileIndex& index = *tiles;
    const size_t texelBytes = 4 * sizeof(uint16_t);
    const size_t rowBytes = texelBytes * static_cast<size_t>(index.map.width);
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
        char* corner = static_cast<char*>(destination) +
                       static_cast<size_t>(row - firstRow) * rowBytes +
                       static_cast<size_t>(column) * index.tileSize * texelBytes;
        readRows(rowTiles[static_cast<size_t>(column)], row - top, bandEnd - top, Imf::HALF, corner,
                 rowBytes);
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
    } else if (isGeoTiffPath(path)) {
      impl_->geotiff.emplace(path, header_);
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
  if (impl_->geotiff) {
    readGeoTiffHalfRows(*impl_->geotiff, header_.width, firstRow, endRow, destination);
    return;
  }
  readRows(*impl_->input, firstRow, endRow, Imf::HALF, destination,
           4 * sizeof(uint16_t) * static_cast<size_t>(header_.width));
}

void ApertureMapReader::verify() {
  // Bands of up to kBlockRows rows and 64 MiB of halves.
  const size_t rowBytes = 4 * sizeof(uint16_t) * static_cast<size_t>(header_.width);
  const int band =
      std::min(header_.height,
               static_cast<int>(std::clamp<size_t>((size_t{64} << 20) / rowBytes, 1, kBlockRows)));
  std::vector<char> rows(rowBytes * static_cast<size_t>(band));
  for (int y = 0; y < header_.height; y += band) {
    readHalfRows(y, std::min(header_.height, y + band), rows.data());
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
  // An older map carries the version 1 checksum: computed for it.
  if (!heightfieldMatchesChecksum(field, map.info.sourceChecksum)) {
    // Another z scale (a vertical exaggeration is one) changes every height:
    // say so, and how to get a matching map.
    if (map.info.zScale > 0 &&
        std::abs(map.info.zScale - field.zScale) > 1e-6 * std::max(map.info.zScale, field.zScale)) {
      char scales[160];
      std::snprintf(scales, sizeof scales,
                    "it was baked for heights at z scale %.9g, these are at %.9g", map.info.zScale,
                    field.zScale);
      char fix[120];
      std::snprintf(fix, sizeof fix, "aal-bake --z-scale %.9g", field.zScale);
      throw InputError(pair + ": " + scales +
                       " (the file's z scale times --z-scale or --exaggeration); bake it with " +
                       fix + ", or leave out --aperture to bake one into the cache");
    }
    throw InputError(pair + ": it was baked from other heights (" + map.info.source +
                     "); bake it again with aal-bake");
  }
  // The heights' checksum does not see the cell size, yet the horizons scale
  // with it. The header stores it as a float and the tile index in 17 digits.
  const auto differs = [](double baked, double now) {
    return baked > 0 && std::abs(baked - now) > 1e-6 * std::max(baked, now);
  };
  if (differs(map.info.cellSizeX, field.cellSizeXM) ||
      differs(map.info.cellSizeY, field.cellSizeYM)) {
    throw InputError(pair + ": it was baked for cells of " + formatMetres(map.info.cellSizeX) +
                     " x " + formatMetres(map.info.cellSizeY) + " m, the DEM has " +
                     formatMetres(field.cellSizeXM) + " x " + formatMetres(field.cellSizeYM) +
                     " m; give the bake's --cell-size, or bake it again with this one");
  }
}

void checkApertureMatchesDem(const ApertureMap& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath) {
  checkApertureMatchesDem(ApertureMapHeader{map.width, map.height, map.info}, mapPath, field,
                          demPath);
}

}  // namespace aal
