#include "hgt_reader.h"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <vector>

#include "errors.h"

namespace aal {

namespace {

constexpr int kSides[] = {1201, 3601};

size_t hgtBytes(int side) {
  return static_cast<size_t>(side) * static_cast<size_t>(side) * 2;
}

std::string expectedSizes() {
  return std::to_string(hgtBytes(1201)) + " (1201 x 1201, 3\") or " +
         std::to_string(hgtBytes(3601)) + " (3601 x 3601, 1\")";
}

std::optional<int> hgtSide(size_t bytes) {
  for (int side : kSides) {
    if (bytes == hgtBytes(side)) return side;
  }
  return std::nullopt;
}

bool digits(const std::string& text, size_t begin, size_t count) {
  for (size_t i = begin; i < begin + count; ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i]))) return false;
  }
  return true;
}

}  // namespace

std::optional<HgtTileName> parseHgtTileName(const std::string& path) {
  const std::string name = std::filesystem::path(path).filename().string();
  if (name.size() < 7) return std::nullopt;
  const char ns = static_cast<char>(std::toupper(static_cast<unsigned char>(name[0])));
  const char ew = static_cast<char>(std::toupper(static_cast<unsigned char>(name[3])));
  if ((ns != 'N' && ns != 'S') || (ew != 'E' && ew != 'W') || !digits(name, 1, 2) ||
      !digits(name, 4, 3)) {
    return std::nullopt;
  }
  const int lat = std::stoi(name.substr(1, 2));
  const int lon = std::stoi(name.substr(4, 3));
  HgtTileName tile{ns == 'N' ? lat : -lat, ew == 'E' ? lon : -lon};
  if (tile.southLatDeg < -90 || tile.southLatDeg > 89 || tile.westLonDeg < -180 ||
      tile.westLonDeg > 179) {
    throw InputError(path + ": inconsistent georeferencing: '" + name.substr(0, 7) +
                     "' names no SRTM tile (south edge must be in [S90, N89], west edge in "
                     "[W180, E179])");
  }
  return tile;
}

RawDem parseHgt(const std::string& path, std::span<const uint8_t> bytes,
                const DemLoadOptions& options) {
  const std::optional<int> side = hgtSide(bytes.size());
  if (!side) {
    throw InputError(path + ": SRTM .hgt file of " + std::to_string(bytes.size()) +
                     " bytes; expected " + expectedSizes());
  }
  const std::optional<HgtTileName> tile = parseHgtTileName(path);
  RawDem dem;
  dem.format = "SRTM HGT";
  dem.sampleType = "int16";
  dem.allocate(*side, *side);
  for (size_t i = 0; i < dem.texelCount(); ++i) {
    const auto sample =
        static_cast<int16_t>(static_cast<uint16_t>(bytes[2 * i] << 8 | bytes[2 * i + 1]));
    if (sample == kHgtVoid) {
      dem.voidMask[i] = 1;
    } else {
      dem.z[i] = sample;
    }
  }
  if (tile) {
    dem.geo.crs = CrsKind::Geographic;
    dem.geo.epsg = 4326;
    dem.geo.stepX = dem.geo.stepY = 1.0 / (*side - 1);
    dem.geo.originX = tile->westLonDeg;
    dem.geo.originY = tile->southLatDeg + 1.0;
  } else if (options.warn) {
    options.warn(path +
                 ": the file name does not give the tile position (like N36W085.hgt); "
                 "the DEM is not georeferenced");
  }
  return dem;
}

RawDem readHgt(const std::string& path, const DemLoadOptions& options) {
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (error) throw InputError(path + ": cannot read: " + error.message());
  if (!hgtSide(size)) {
    throw InputError(path + ": SRTM .hgt file of " + std::to_string(size) + " bytes; expected " +
                     expectedSizes());
  }
  std::vector<uint8_t> bytes(size);
  std::ifstream in(path, std::ios::binary);
  if (!in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
    throw InputError(path + ": cannot read all " + std::to_string(size) + " bytes");
  }
  return parseHgt(path, bytes, options);
}

}  // namespace aal
