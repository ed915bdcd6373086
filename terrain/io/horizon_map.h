// Directional horizons (issue 18): per texel the horizon's elevation in 8
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
bool validHorizonDirections(int directions);

// The stored elevation range. 8-bit codes 0..255 map to [kHorizonMinRad,
// kHorizonMaxRad] with code = 255 sqrt((e - min) / (max - min)), so steps
// are finest near the horizontal where low suns are (0.11 degrees at 0,
// 0.26 at 10, 0.43 at 30 degrees). 4-bit codes 0..15 (twice the directions
// in the same memory, docs/comparison.md) spend their 16 levels on
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

// The device lays the directions out four to an RGBA layer (engine/
// terrain_scene.h), rotated by r = 0 or 2: layer l holds directions
// (4l + r) .. (4l + r + 3) mod n as R, G, B, A. The two stored directions
// beside an azimuth lie in one layer for at least one of the two rotations
// (the layers' seams of one lie mid-layer of the other), so the horizon
// mode fetches one layer per fragment whatever the sun, the renderer
// re-laying the layers when the sun crosses a seam (docs/rendering.md, the
// horizon mode).
constexpr int kHorizonRotations[] = {0, 2};
bool validHorizonRotation(int rotation);  // 0 or 2
// Whether both stored directions beside azimuthRad lie in one layer when
// the layers are rotated by `rotation`.
bool horizonRotationServes(int directions, float azimuthRad, int rotation);
// The rotation to draw a sun at azimuthRad with: `currentRotation` while it
// serves the azimuth and the sun is more than kHorizonRotationMargin of a
// direction step from its seams (hysteresis: a sun resting on a seam, or
// jittering about it, does not re-lay every frame), else the other one
// (which then serves with that margin). `currentRotation` outside 0 and 2
// (none laid yet): whichever serves with the margin, 0 when both do.
// Always a rotation that serves azimuthRad.
constexpr float kHorizonRotationMargin = 0.125f;
int horizonRotationFor(int directions, float azimuthRad, int currentRotation);

// What a shader needs to read the horizon at one azimuth from the device's
// layers rotated by `rotation`: the layer of the two stored directions
// beside the azimuth and, per channel, the weight of the code's power p(u)
// (u = code / (2^bits - 1); p(u) = u^2 for 8-bit codes, u^1.5 for 4-bit
// ones), the interpolation's weight and the decode's scale in one, so that
//   horizon = kHorizonMinRad + dot(p(layer), weights)
// equals horizonAtAzimuth (up to float rounding): one fetch. The sun is the
// frame's, so the renderer computes this once per frame instead of every
// fragment (docs/rendering.md, the horizon mode). Throws
// std::invalid_argument where `rotation` does not serve the azimuth
// (horizonRotationFor picks one that does).
struct HorizonLayerWeights {
  int layer = 0;
  std::array<float, 4> weights{};
};
HorizonLayerWeights horizonLayerWeights(int directions, float azimuthRad, int bits, int rotation);

// Writes / reads the file format of docs/baking.md ("aperture-horizons 3"
// header line with the code bits and the DEM's checksum, then the codes;
// version 2 files have no checksum, version 1 files neither the bits: they
// hold 8-bit codes). Writing needs the checksum. Reading throws
// std::runtime_error naming the file for anything that is not such a file or
// is truncated.
void writeHorizonMap(const std::filesystem::path& path, const HorizonMap& map);
HorizonMap readHorizonMap(const std::filesystem::path& path);

}  // namespace aal
