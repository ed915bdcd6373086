// The DEM identity an aperture map carries (aal:sourceChecksum,
// docs/baking.md "Output"). Two versions, told apart by their text:
//
// - Version 2, "r2-" and 16 hex digits (every bake writes it): 64-bit FNV-1a
//   over the width and height (int32) and then, in row order, each row's
//   XXH64 (seed 0) of its heights as float32, all little-endian. Rows are
//   hashed apart, so any thread or MPI rank can hash any rows; only the
//   combination (8 bytes a row) is in order.
// - Version 1, 16 hex digits without a prefix (older maps, caches and tiled
//   folders): 64-bit FNV-1a over the width, the height and every height in
//   row order, byte by byte, which no two processes can share. Still
//   computed to check the files users hold.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "aperture/terrain/heightfield.h"

namespace aal {

// What precedes the 16 hex digits of a version 2 (row-hash) checksum.
constexpr const char* kRowHashChecksumPrefix = "r2-";

// A row's part of the checksum: XXH64 of its `width` heights' bytes.
uint64_t heightRowHash(const float* row, int width);
// The checksum of a width x height DEM from its rows' hashes, in order.
std::string rowHashChecksum(int width, int height, const uint64_t* rowHashes);

// Whether `checksum` is of version 1, the byte-serial FNV-1a (16 hex digits
// without a prefix).
bool isLegacyHeightChecksum(const std::string& checksum);

// The version 1 (byte-serial) checksum, fed in parts.
class LegacyHeightfieldHasher {
 public:
  LegacyHeightfieldHasher(int width, int height);
  // The next `count` heights in row order.
  void add(const float* heights, size_t count);
  std::string hex() const;

 private:
  uint64_t hash_;
};

// The version 2 checksum every bake writes, of a field holding all its rows
// (the rows hashed on all cores).
std::string heightfieldChecksum(const Heightfield& field);
// The version 1 checksum older maps carry.
std::string legacyHeightfieldChecksum(const Heightfield& field);
// Whether `recorded` (a map's aal:sourceChecksum, of either version) is the
// checksum of `field`: computed in the version `recorded` has.
bool heightfieldMatchesChecksum(const Heightfield& field, const std::string& recorded);

}  // namespace aal
