#include "aperture/terrain/io/horizon_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <system_error>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/io/pixel_checksum.h"

namespace aal {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
constexpr const char* kMagic = "aperture-horizons";
// 4: the codes' checksum; 3: none of the codes; 2: no heights checksum
// either; 1: 8-bit codes, no bits field.
constexpr int kVersion = 4;

// The checksum of the codes (docs/baking.md, "Directional horizons"): the
// aperture map's pixel checksum (pixel_checksum.h) over the rows of texels,
// each row the width x directions codes as stored.
uint64_t codesChecksum(const HorizonMap& map) {
  PixelChecksum sum(map.height);
  const size_t rowBytes = size_t(map.width) * size_t(map.directions);
  for (int row = 0; row < map.height; ++row) {
    sum.addRow(row, map.codes.data() + size_t(row) * rowBytes, rowBytes);
  }
  return sum.value();
}

// A checksum as the header carries it: one word, printable.
bool validChecksumWord(const std::string& checksum) {
  return !checksum.empty() && checksum.size() <= 64 &&
         std::all_of(checksum.begin(), checksum.end(), [](char c) { return c > ' ' && c < 127; });
}

}  // namespace

bool validHorizonDirections(int directions) {
  return directions >= 4 && directions <= kMaxHorizonDirections && directions % 4 == 0;
}

bool validHorizonBits(int bits) {
  return bits == 8 || bits == 4;
}

float decodeHorizonUnorm(float unorm, int bits) {
  if (bits == 4) {
    return kHorizonMinRad + unorm * std::sqrt(unorm) * (kHorizon4BitMaxRad - kHorizonMinRad);
  }
  return kHorizonMinRad + unorm * unorm * (kHorizonMaxRad - kHorizonMinRad);
}

uint8_t encodeHorizon(float elevationRad, int bits) {
  if (!(elevationRad > kHorizonMinRad)) return 0;  // NaN (no terrain ahead) too
  if (bits == 4) {
    // The nearest of the 16 levels in elevation (the code's spacing grows
    // with the elevation, so rounding the code would not be).
    const float x =
        std::min(1.0f, (elevationRad - kHorizonMinRad) / (kHorizon4BitMaxRad - kHorizonMinRad));
    const int below = std::min(14, int(15.0f * std::cbrt(x * x)));
    const float lower = decodeHorizon(uint8_t(below), 4),
                upper = decodeHorizon(uint8_t(below + 1), 4);
    return uint8_t(elevationRad - lower <= upper - elevationRad ? below : below + 1);
  }
  const float x =
      std::min(1.0f, (elevationRad - kHorizonMinRad) / (kHorizonMaxRad - kHorizonMinRad));
  return static_cast<uint8_t>(std::lround(255.0f * std::sqrt(x)));
}

float decodeHorizon(uint8_t code, int bits) {
  return decodeHorizonUnorm(float(code) / float((1 << bits) - 1), bits);
}

namespace {

// The azimuth in direction steps, [0, n) (what horizonNeighbours reads).
float directionPosition(int directions, float azimuthRad) {
  const float n = float(directions);
  float x = azimuthRad / kTwoPi * n;
  x -= n * std::floor(x / n);  // [0, n)
  return x;
}

// The two of `directions` stored azimuths beside azimuthRad, and the weight f
// of the second: the horizon is linear between them.
struct HorizonNeighbours {
  int k0 = 0, k1 = 0;
  float f = 0;
};

HorizonNeighbours neighboursAt(int directions, float x) {
  HorizonNeighbours h;
  h.k0 = std::min(int(x), directions - 1);
  h.k1 = (h.k0 + 1) % directions;
  h.f = x - float(h.k0);
  return h;
}

HorizonNeighbours horizonNeighbours(int directions, float azimuthRad) {
  return neighboursAt(directions, directionPosition(directions, azimuthRad));
}

// x - first in direction steps, wrapped into [-n/2, n/2).
float stepsPast(int directions, float x, int first) {
  const float n = float(directions);
  float d = x - float(first);
  d -= n * std::floor(d / n + 0.5f);
  return d;
}

}  // namespace

float horizonAtAzimuth(const uint8_t* codes, int directions, float azimuthRad, int bits) {
  const HorizonNeighbours h = horizonNeighbours(directions, azimuthRad);
  return (1.0f - h.f) * decodeHorizon(codes[h.k0], bits) + h.f * decodeHorizon(codes[h.k1], bits);
}

bool validHorizonPair(int directions, int first) {
  return validHorizonDirections(directions) && first >= 0 && first < directions;
}

int horizonPairFor(int directions, float azimuthRad, int currentFirst, float margin) {
  const float x = directionPosition(directions, azimuthRad);
  if (validHorizonPair(directions, currentFirst)) {
    const float d = stepsPast(directions, x, currentFirst);
    if (d >= -margin && d <= 1.0f + margin) return currentFirst;
  }
  return neighboursAt(directions, x).k0;
}

float horizonStepsFrom(int directions, float azimuthRad, int direction) {
  return stepsPast(directions, directionPosition(directions, azimuthRad), direction);
}

std::array<float, 2> horizonPairWeights(int directions, float azimuthRad, int first) {
  if (!validHorizonPair(directions, first)) {
    throw std::invalid_argument("horizonPairWeights: direction " + std::to_string(first) + " of " +
                                std::to_string(directions));
  }
  const float f = std::clamp(
      stepsPast(directions, directionPosition(directions, azimuthRad), first), 0.0f, 1.0f);
  return {1.0f - f, f};
}

void writeHorizonMap(const std::filesystem::path& path, const HorizonMap& map) {
  if (map.width < 1 || map.height < 1 || !validHorizonDirections(map.directions) ||
      !validHorizonBits(map.bits) || !validChecksumWord(map.sourceChecksum) ||
      map.codes.size() != size_t(map.width) * size_t(map.height) * size_t(map.directions) ||
      std::any_of(map.codes.begin(), map.codes.end(),
                  [&](uint8_t c) { return c >= (1 << map.bits); })) {
    throw std::invalid_argument("writeHorizonMap: inconsistent map");
  }
  AtomicOutput output(path);
  {
    std::ofstream out(output.temporaryPath(), std::ios::binary);
    out << kMagic << ' ' << kVersion << ' ' << map.width << ' ' << map.height << ' '
        << map.directions << ' ' << map.bits << ' ' << map.sourceChecksum << ' '
        << checksumHex(codesChecksum(map)) << '\n';
    out.write(reinterpret_cast<const char*>(map.codes.data()),
              static_cast<std::streamsize>(map.codes.size()));
    out.flush();
    if (!out) throw output.failure("write failed", "horizons");
  }
  output.commit();
}

HorizonMap readHorizonMap(const std::filesystem::path& path) {
  // Looked at before it is opened: a FIFO would block the open forever.
  if (requireFileOrFolder(path.string(), "horizon map " + path.string()) == InputKind::Folder) {
    throw std::runtime_error("horizon map " + path.string() + " is a folder, not a file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open horizons " + path.string());
  std::string header;
  std::getline(in, header);
  std::istringstream fields(header);
  std::string magic, codes;
  int version = 0;
  HorizonMap map;
  fields >> magic >> version >> map.width >> map.height >> map.directions;
  map.bits = kHorizonBits;
  if (version >= 2) fields >> map.bits;
  if (version >= 3) fields >> map.sourceChecksum;
  if (version >= 4) fields >> codes;
  const std::optional<uint64_t> expected = parseChecksumHex(codes);
  if (!fields || magic != kMagic || version < 1 || version > kVersion ||
      (version >= 3 && !validChecksumWord(map.sourceChecksum)) || (version >= 4 && !expected) ||
      !validHorizonDirections(map.directions) || !validHorizonBits(map.bits) || map.width < 1 ||
      map.height < 1 || map.width > (1 << 20) || map.height > (1 << 20)) {
    throw std::runtime_error(path.string() + " is not a horizon map (\"" + kMagic + " " +
                             std::to_string(kVersion) +
                             " WIDTH HEIGHT DIRECTIONS BITS CHECKSUM CODES-CHECKSUM\" with 4, 8, "
                             "12 or 16 directions of 8 or 4 bits)");
  }
  // The header's size against the file's before allocating: a damaged
  // header must not ask for terabytes.
  const size_t codeCount = size_t(map.width) * size_t(map.height) * size_t(map.directions);
  std::error_code error;
  const uintmax_t fileBytes = std::filesystem::file_size(path, error);
  if (!error && fileBytes < uintmax_t(in.tellg()) + codeCount) {
    throw std::runtime_error("horizon map " + path.string() + " is truncated");
  }
  map.codes.resize(codeCount);
  in.read(reinterpret_cast<char*>(map.codes.data()),
          static_cast<std::streamsize>(map.codes.size()));
  if (in.gcount() != static_cast<std::streamsize>(map.codes.size())) {
    throw std::runtime_error("horizon map " + path.string() + " is truncated");
  }
  if (expected) {
    if (const uint64_t actual = codesChecksum(map); actual != *expected) {
      throw InputError("horizon map " + path.string() +
                       " is corrupt: its codes do not match the checksum in its header (" +
                       checksumHex(*expected) + ", codes " + checksumHex(actual) +
                       "); bake it again (aal-bake DEM --horizons FILE)");
    }
  }
  const int maxCode = (1 << map.bits) - 1;
  if (std::any_of(map.codes.begin(), map.codes.end(), [&](uint8_t c) { return c > maxCode; })) {
    throw std::runtime_error("horizon map " + path.string() + " holds codes above " +
                             std::to_string(maxCode) + " for " + std::to_string(map.bits) +
                             "-bit codes");
  }
  return map;
}

}  // namespace aal
