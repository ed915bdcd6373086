// The DEM identity an aperture map carries (aal:sourceChecksum), computed
// in parts: 64-bit FNV-1a over the width, the height and every height in
// row order, as 16 hex digits. heightfieldChecksum (aperture_map.h) is the
// same over a whole heightfield; a tiled bake of a DEM larger than memory
// feeds it band by band.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace aal {

class HeightfieldHasher {
 public:
  HeightfieldHasher(int width, int height);
  // The next `count` heights in row order.
  void add(const float* heights, size_t count);
  std::string hex() const;

 private:
  void mix(const void* data, size_t bytes);
  uint64_t hash_ = 0xcbf29ce484222325ull;
};

}  // namespace aal
