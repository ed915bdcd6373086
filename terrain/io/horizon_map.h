// Directional horizons: per texel the horizon's elevation in 8
// (or 4, 12, 16) azimuths, 8 or 4 bits each, beside the aperture map. The sun
// is tiny, so whether a texel sees it depends on the horizon in the sun's
// azimuth, which one aperture cap summarises poorly at a low sun
// (docs/comparison.md); the `horizon` shading mode (terrain/light/shading.h) takes
// the sun's visible fraction from these horizons and the sky fill from the
// aperture. Format and encoding: docs/baking.md, "Directional horizons".
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace aal {

// Azimuths stored per texel by default: k * 360 / n degrees counter-clockwise
// from east (the bake's azimuth convention), k = 0..n-1; n a multiple of 4
// (RGBA8 layers on the device) up to kMaxHorizonDirections.
constexpr int kHorizonDirections = 8;
constexpr int kMaxHorizonDirections = 16;
// What aal-bake --horizons writes unless asked: 16 directions of 8-bit codes,
// the horizon mode's lowest error (mean over 16 low suns, docs/comparison.md:
// 3.44 % against 3.52 % for 16 of 4 bits and 4.17 % for 8 of 8 bits). A code
// takes a byte whatever its bits, in the file and the host's memory, and the
// device holds only the decoded pair beside the sun, so 4-bit codes save
// nothing. The in-memory bakes of aal-view and Python render() keep the same.
constexpr int kBakeToolHorizonDirections = 16;
constexpr int kBakeToolHorizonBits = 8;
bool validHorizonDirections(int directions);

// The stored elevation range. 8-bit codes 0..255 map to [kHorizonMinRad,
// kHorizonMaxRad] with code = 255 sqrt((e - min) / (max - min)), so steps
// are finest near the horizontal where low suns are (0.11 degrees at 0,
// 0.26 at 10, 0.43 at 30 degrees). 4-bit codes 0..15 (one byte each all the
// same: a format for a packed store, docs/comparison.md) spend their 16 levels on
// [kHorizonMinRad, kHorizon4BitMaxRad] with code = 15 ((e - min) / (max -
// min))^(2/3): levels 1.9 degrees apart near the horizontal, 3.1 at 10
// degrees, 4.6 at 40; higher horizons read as 45 degrees (a sun above 45 degrees is
// not shadowed by them). Lower horizons (open ground, peaks) read as the
// minimum, 2 degrees below the horizontal: a sun above it is wholly visible
// there.
constexpr float kHorizonMinRad = -0.034906585f;    // -2 degrees
constexpr float kHorizonMaxRad = 1.5707963f;       // 90 degrees
constexpr float kHorizon4BitMaxRad = 0.78539816f;  // 45 degrees
constexpr int kHorizonBits = 8;
bool validHorizonBits(int bits);  // 8 or 4

uint8_t encodeHorizon(float elevationRad, int bits = kHorizonBits);
float decodeHorizon(uint8_t code, int bits = kHorizonBits);
// The same from code / (2^bits - 1), as the device samples (and filters) it.
float decodeHorizonUnorm(float unorm, int bits);

struct HorizonMap {
  int width = 0, height = 0;
  int directions = kHorizonDirections;
  int bits = kHorizonBits;  // of each code (one code per byte in memory and file)
  // heightfieldChecksum() of the DEM they were baked from (terrain/io/
  // heightfield_checksum.h), as the aperture map's; empty in files of
  // versions 1 and 2, which predate it (then only the size can be checked).
  std::string sourceChecksum;
  // `directions` codes per texel, rows top (north) to bottom as the aperture
  // map's, directions in order.
  std::vector<uint8_t> codes;

  const uint8_t* texel(int col, int row) const {
    return &codes[(size_t(row) * size_t(width) + size_t(col)) * size_t(directions)];
  }
};

// The horizon elevation (rad) in azimuth azimuthRad (counter-clockwise from
// east), linear between the two of `directions` stored directions beside it.
float horizonAtAzimuth(const uint8_t* codes, int directions, float azimuthRad,
                       int bits = kHorizonBits);

// The device holds, per texel, the horizons of two adjacent stored
// directions, `first` and first + 1 mod n, decoded to radians in the slope
// texture's spare channels (engine/terrain_scene.h setHorizons): the pair
// beside the frame's sun, so the horizon mode reads the sun's horizon in
// the same fetch as the normal. The renderer lays the pair again when the
// sun leaves it (docs/rendering.md, the horizon mode).
//
// The pair to draw a sun at azimuthRad with: `currentFirst` while the sun
// lies within that pair's span widened by kHorizonPairMargin direction
// steps on either side (hysteresis: a sun resting on a stored direction, or
// jittering about it, does not re-lay every frame), else the pair whose span
// holds the sun. `currentFirst` outside [0, directions) (none laid yet): the
// pair whose span holds the sun. `margin` (steps): the renderer's spread
// re-lays keep a wider one (engine/horizon_relay.h).
constexpr float kHorizonPairMargin = 0.0625f;
bool validHorizonPair(int directions, int first);  // 0 <= first < directions
int horizonPairFor(int directions, float azimuthRad, int currentFirst,
                   float margin = kHorizonPairMargin);
// Direction steps (2 pi / n) from stored direction `direction` to azimuthRad,
// wrapped into [-n/2, n/2).
float horizonStepsFrom(int directions, float azimuthRad, int direction);
// The weights of the pair's two horizons for a sun at azimuthRad, so that
//   horizon = weights[0] h(first) + weights[1] h(first + 1)
// equals horizonAtAzimuth (up to float rounding) wherever the sun lies in
// the pair's span; within the margin outside it the nearer direction's
// horizon (weights 1, 0 or 0, 1). The sun is the frame's, so the renderer
// computes them once per frame, not per fragment. Throws
// std::invalid_argument for an invalid pair.
std::array<float, 2> horizonPairWeights(int directions, float azimuthRad, int first);

// Writes / reads the file format of docs/baking.md ("aperture-horizons 4"
// header line with the code bits, the DEM's checksum and the checksum of
// the codes, then the codes; version 3 files have no checksum of the codes,
// version 2 files neither the DEM's, version 1 files neither the bits: they
// hold 8-bit codes). Writing needs the DEM's checksum. Reading throws
// std::runtime_error naming the file for anything that is not such a file
// or is truncated, and InputError naming it when it is not a regular file
// or folder (a FIFO, a device: not opened) or, from version 4 on, when its
// codes do not match their checksum (damaged: bake it again).
void writeHorizonMap(const std::filesystem::path& path, const HorizonMap& map);
HorizonMap readHorizonMap(const std::filesystem::path& path);

}  // namespace aal
