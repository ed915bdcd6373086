#include "aperture/terrain/io/heightfield_checksum.h"

#include <cctype>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "aperture/terrain/io/pixel_checksum.h"

namespace aal {

namespace {

constexpr uint64_t kFnvOffset = 0xcbf29ce484222325ull;
constexpr uint64_t kFnvPrime = 0x100000001b3ull;

// 64-bit FNV-1a (Fowler, Noll and Vo) of `bytes` bytes, continuing `hash`.
uint64_t fnv1a(uint64_t hash, const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < bytes; ++i) {
    hash ^= p[i];
    hash *= kFnvPrime;
  }
  return hash;
}

std::string hex16(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

void requireWholeField(const Heightfield& field) {
  if (field.z.size() != field.texelCount()) {
    throw std::invalid_argument("heights checksum: the field must hold all its rows");
  }
}

}  // namespace

uint64_t heightRowHash(const float* row, int width) {
  return xxh64(row, static_cast<size_t>(width) * sizeof(float), 0);
}

std::string rowHashChecksum(int width, int height, const uint64_t* rowHashes) {
  uint64_t hash = fnv1a(kFnvOffset, &width, sizeof width);
  hash = fnv1a(hash, &height, sizeof height);
  hash = fnv1a(hash, rowHashes, static_cast<size_t>(height) * sizeof(uint64_t));
  return kRowHashChecksumPrefix + hex16(hash);
}

bool isLegacyHeightChecksum(const std::string& checksum) {
  if (checksum.size() != 16) return false;
  for (char c : checksum) {
    if (!std::isxdigit(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

LegacyHeightfieldHasher::LegacyHeightfieldHasher(int width, int height) {
  hash_ = fnv1a(kFnvOffset, &width, sizeof width);
  hash_ = fnv1a(hash_, &height, sizeof height);
}

void LegacyHeightfieldHasher::add(const float* heights, size_t count) {
  hash_ = fnv1a(hash_, heights, count * sizeof(float));
}

std::string LegacyHeightfieldHasher::hex() const {
  return hex16(hash_);
}

std::string heightfieldChecksum(const Heightfield& field) {
  requireWholeField(field);
  std::vector<uint64_t> hashes(static_cast<size_t>(field.height));
  tbb::parallel_for(
      tbb::blocked_range<int>(0, field.height), [&](const tbb::blocked_range<int>& r) {
        for (int y = r.begin(); y < r.end(); ++y) {
          hashes[static_cast<size_t>(y)] =
              heightRowHash(field.z.data() + static_cast<size_t>(y) * field.width, field.width);
        }
      });
  return rowHashChecksum(field.width, field.height, hashes.data());
}

std::string legacyHeightfieldChecksum(const Heightfield& field) {
  requireWholeField(field);
  LegacyHeightfieldHasher hasher(field.width, field.height);
  hasher.add(field.z.data(), field.z.size());
  return hasher.hex();
}

bool heightfieldMatchesChecksum(const Heightfield& field, const std::string& recorded) {
  return recorded == (isLegacyHeightChecksum(recorded) ? legacyHeightfieldChecksum(field)
                                                       : heightfieldChecksum(field));
}

}  // namespace aal
