#include "horizon_map.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>

#include "atomic_file.h"

namespace aal {

namespace {

constexpr float kTwoPi = 2.0f * std::numbers::pi_v<float>;
constexpr const char* kMagic = "aperture-horizons";
constexpr int kVersion = 1;

}  // namespace

bool validHorizonDirections(int directions) {
  return directions >= 4 && directions <= kMaxHorizonDirections && directions % 4 == 0;
}

uint8_t encodeHorizon(float elevationRad) {
  if (!(elevationRad > kHorizonMinRad)) return 0;  // NaN (no terrain ahead) too
  const float x =
      std::min(1.0f, (elevationRad - kHorizonMinRad) / (kHorizonMaxRad - kHorizonMinRad));
  return static_cast<uint8_t>(std::lround(255.0f * std::sqrt(x)));
}

float decodeHorizon(uint8_t code) {
  const float c = float(code) / 255.0f;
  return kHorizonMinRad + c * c * (kHorizonMaxRad - kHorizonMinRad);
}

float horizonAtAzimuth(const uint8_t* codes, int directions, float azimuthRad) {
  const float n = float(directions);
  float x = azimuthRad / kTwoPi * n;
  x -= n * std::floor(x / n);  // [0, n)
  const int k0 = std::min(int(x), directions - 1);
  const int k1 = (k0 + 1) % directions;
  const float f = x - float(k0);
  return (1.0f - f) * decodeHorizon(codes[k0]) + f * decodeHorizon(codes[k1]);
}

void writeHorizonMap(const std::filesystem::path& path, const HorizonMap& map) {
  if (map.width < 1 || map.height < 1 || !validHorizonDirections(map.directions) ||
      map.codes.size() != size_t(map.width) * size_t(map.height) * size_t(map.directions)) {
    throw std::invalid_argument("writeHorizonMap: inconsistent map");
  }
  AtomicOutput output(path);
  {
    std::ofstream out(output.temporaryPath(), std::ios::binary);
    out << kMagic << ' ' << kVersion << ' ' << map.width << ' ' << map.height << ' '
        << map.directions << '\n';
    out.write(reinterpret_cast<const char*>(map.codes.data()),
              static_cast<std::streamsize>(map.codes.size()));
    out.flush();
    if (!out) throw output.failure("write failed", "horizons");
  }
  output.commit();
}

HorizonMap readHorizonMap(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open horizons " + path.string());
  std::string header;
  std::getline(in, header);
  std::istringstream fields(header);
  std::string magic;
  int version = 0;
  HorizonMap map;
  fields >> magic >> version >> map.width >> map.height >> map.directions;
  if (!fields || magic != kMagic || version != kVersion ||
      !validHorizonDirections(map.directions) || map.width < 1 || map.height < 1 ||
      map.width > (1 << 20) || map.height > (1 << 20)) {
    throw std::runtime_error(path.string() + " is not a horizon map (\"" + kMagic + " " +
                             std::to_string(kVersion) + "\" with 4, 8, 12 or 16 directions)");
  }
  map.codes.resize(size_t(map.width) * size_t(map.height) * size_t(map.directions));
  in.read(reinterpret_cast<char*>(map.codes.data()),
          static_cast<std::streamsize>(map.codes.size()));
  if (in.gcount() != static_cast<std::streamsize>(map.codes.size())) {
    throw std::runtime_error("horizon map " + path.string() + " is truncated");
  }
  return map;
}

}  // namespace aal
