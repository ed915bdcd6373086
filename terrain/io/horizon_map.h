// Directional horizons (issue 18): per texel the horizon's elevation in 8
// (or 4, 12, 16) azimuths, 8 bits each, beside the aperture map. The sun
// is tiny, so whether a texel sees it depends on the horizon in the sun's
// azimuth, which one aperture cap summarises poorly at a low sun
// (docs/comparison.md); the `horizon` shading mode (terrain/light/shading.h) takes
// the sun's visible fraction from these horizons and the sky fill from the
// aperture. Format and encoding: docs/baking.md, "Directional horizons".
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

namespace aal {

// Azimuths stored per texel by default: k * 360 / n degrees counter-clockwise
// from east (the bake's azimuth convention), k = 0..n-1; n a multiple of 4
// (RGBA8 layers on the device) up to kMaxHorizonDirections.
constexpr int kHorizonDirections = 8;
constexpr int kMaxHorizonDirections = 16;
bool validHorizonDirections(int directions);

// The stored elevation range: codes 0..255 map to [kHorizonMinRad,
// kHorizonMaxRad] with code = 255 sqrt((e - min) / (max - min)), so steps
// are finest near the horizontal where low suns are (0.11 degrees at 0,
// 0.26 at 10, 0.43 at 30 degrees). Lower horizons (open ground, peaks)
// read as the minimum, 2 degrees below the horizontal: a sun above it is
// wholly visible there.
constexpr float kHorizonMinRad = -0.034906585f;  // -2 degrees
constexpr float kHorizonMaxRad = 1.5707963f;     // 90 degrees

uint8_t encodeHorizon(float elevationRad);
float decodeHorizon(uint8_t code);

struct HorizonMap {
  int width = 0, height = 0;
  int directions = kHorizonDirections;
  // `directions` codes per texel, rows top (north) to bottom as the aperture
  // map's, directions in order.
  std::vector<uint8_t> codes;

  const uint8_t* texel(int col, int row) const {
    return &codes[(size_t(row) * size_t(width) + size_t(col)) * size_t(directions)];
  }
};

// The horizon elevation (rad) in azimuth azimuthRad (counter-clockwise from
// east), linear between the two of `directions` stored directions beside it.
float horizonAtAzimuth(const uint8_t* codes, int directions, float azimuthRad);

// Writes / reads the file format of docs/baking.md ("aperture-horizons 1"
// header line, then the codes). Reading throws std::runtime_error naming the
// file for anything that is not such a file or is truncated.
void writeHorizonMap(const std::filesystem::path& path, const HorizonMap& map);
HorizonMap readHorizonMap(const std::filesystem::path& path);

}  // namespace aal
