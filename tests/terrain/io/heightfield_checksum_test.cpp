// The heights checksum a map carries (aal:sourceChecksum): the row-hash
// version against a straight loop over the rows, the same however its rows
// are split over callers and threads; version 1, the byte-serial checksum of
// older maps, still computed and told apart.
#include "aperture/terrain/io/heightfield_checksum.h"

#include <gtest/gtest.h>

#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "aperture/terrain/io/pixel_checksum.h"

namespace aal {
namespace {

// width x height heights from a seeded generator (any bits a float can
// hold but NaN: negative, tiny, large).
Heightfield randomField(int width, int height, unsigned seed) {
  Heightfield field;
  field.width = width;
  field.height = height;
  field.z.resize(field.texelCount());
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> heights(-500.0f, 9000.0f);
  for (float& z : field.z) z = heights(random);
  return field;
}

// 64-bit FNV-1a, byte by byte, as its authors (Fowler, Noll and Vo) give it.
uint64_t referenceFnv1a(uint64_t hash, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) hash = (hash ^ p[i]) * 0x100000001b3ull;
  return hash;
}

std::string hex(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

// The row-hash checksum as docs/baking.md defines it, one row after another.
std::string referenceChecksum(const Heightfield& field) {
  uint64_t hash = 0xcbf29ce484222325ull;
  const int32_t width = field.width, height = field.height;
  hash = referenceFnv1a(hash, &width, 4);
  hash = referenceFnv1a(hash, &height, 4);
  for (int y = 0; y < field.height; ++y) {
    const uint64_t row =
        xxh64(field.z.data() + static_cast<size_t>(y) * field.width, 4 * size_t(field.width), 0);
    hash = referenceFnv1a(hash, &row, 8);
  }
  return "r2-" + hex(hash);
}

// The version 1 checksum: every byte in order.
std::string referenceLegacyChecksum(const Heightfield& field) {
  uint64_t hash = 0xcbf29ce484222325ull;
  const int32_t width = field.width, height = field.height;
  hash = referenceFnv1a(hash, &width, 4);
  hash = referenceFnv1a(hash, &height, 4);
  hash = referenceFnv1a(hash, field.z.data(), 4 * field.z.size());
  return hex(hash);
}

TEST(HeightfieldChecksum, EqualsAStraightLoopOverTheRows) {
  for (const auto& [width, height] : {std::pair{1, 1}, {7, 3}, {300, 200}, {1, 513}}) {
    const Heightfield field = randomField(width, height, 11);
    const std::string checksum = heightfieldChecksum(field);
    EXPECT_EQ(checksum, referenceChecksum(field)) << width << "x" << height;
    EXPECT_EQ(checksum.size(), 19u);
    EXPECT_EQ(checksum.rfind(kRowHashChecksumPrefix, 0), 0u);
    EXPECT_FALSE(isLegacyHeightChecksum(checksum));
  }
}

TEST(HeightfieldChecksum, LegacyVersionIsTheByteSerialFnv1a) {
  const Heightfield field = randomField(300, 200, 12);
  const std::string legacy = legacyHeightfieldChecksum(field);
  EXPECT_EQ(legacy, referenceLegacyChecksum(field));
  EXPECT_TRUE(isLegacyHeightChecksum(legacy));
  // Fed in parts of any size, as the bands of a bake.
  LegacyHeightfieldHasher parts(field.width, field.height);
  for (size_t first = 0; first < field.z.size(); first += 777) {
    parts.add(field.z.data() + first, std::min<size_t>(777, field.z.size() - first));
  }
  EXPECT_EQ(parts.hex(), legacy);
  EXPECT_FALSE(isLegacyHeightChecksum(""));
  EXPECT_FALSE(isLegacyHeightChecksum("0123456789abcdeg"));
  EXPECT_FALSE(isLegacyHeightChecksum("0123456789abcde"));
}

// Rows hashed by 1, 2 or 3 callers (ranks) in any order, and by 1 or 8
// threads: one checksum.
TEST(HeightfieldChecksum, SameHoweverTheRowsAreSplit) {
  const Heightfield field = randomField(97, 61, 13);
  const std::string want = referenceChecksum(field);
  for (int parts : {1, 2, 3}) {
    std::vector<uint64_t> hashes(static_cast<size_t>(field.height), 0);
    for (int part = parts - 1; part >= 0; --part) {  // the last part first
      const int first = part * field.height / parts, end = (part + 1) * field.height / parts;
      for (int y = first; y < end; ++y) {
        hashes[static_cast<size_t>(y)] =
            heightRowHash(field.z.data() + static_cast<size_t>(y) * field.width, field.width);
      }
    }
    EXPECT_EQ(rowHashChecksum(field.width, field.height, hashes.data()), want) << parts;
  }
  for (size_t threads : {1, 8}) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    EXPECT_EQ(heightfieldChecksum(field), want) << threads << " threads";
  }
}

TEST(HeightfieldChecksum, SeesEveryHeightItsOrderAndTheShape) {
  const Heightfield field = randomField(40, 30, 14);
  const std::string checksum = heightfieldChecksum(field);
  Heightfield changed = field;
  changed.z[35 * 7 + 3] = std::nextafter(changed.z[35 * 7 + 3], 1e9f);
  EXPECT_NE(heightfieldChecksum(changed), checksum);
  Heightfield swapped = field;  // rows 4 and 5 swapped
  std::swap_ranges(swapped.z.begin() + 4 * 40, swapped.z.begin() + 5 * 40,
                   swapped.z.begin() + 5 * 40);
  EXPECT_NE(heightfieldChecksum(swapped), checksum);
  Heightfield transposed = field;  // the same heights as 30 x 40
  transposed.width = 30;
  transposed.height = 40;
  EXPECT_NE(heightfieldChecksum(transposed), checksum);
}

// A map carries either version: each is checked in its own.
TEST(HeightfieldChecksum, AMapOfEitherVersionMatchesItsDemOnly) {
  const Heightfield field = randomField(50, 20, 15), other = randomField(50, 20, 16);
  for (const std::string& recorded :
       {heightfieldChecksum(field), legacyHeightfieldChecksum(field)}) {
    EXPECT_TRUE(heightfieldMatchesChecksum(field, recorded)) << recorded;
    EXPECT_FALSE(heightfieldMatchesChecksum(other, recorded)) << recorded;
  }
  EXPECT_FALSE(heightfieldMatchesChecksum(field, ""));
  EXPECT_FALSE(heightfieldMatchesChecksum(field, "r2-" + legacyHeightfieldChecksum(field)));
}

}  // namespace
}  // namespace aal
