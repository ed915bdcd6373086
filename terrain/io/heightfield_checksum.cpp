#include "heightfield_checksum.h"

#include <cstdio>

namespace aal {

HeightfieldHasher::HeightfieldHasher(int width, int height) {
  mix(&width, sizeof width);
  mix(&height, sizeof height);
}

void HeightfieldHasher::add(const float* heights, size_t count) {
  mix(heights, count * sizeof(float));
}

void HeightfieldHasher::mix(const void* data, size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  uint64_t hash = hash_;
  for (size_t i = 0; i < bytes; ++i) {
    hash ^= p[i];
    hash *= 0x100000001b3ull;
  }
  hash_ = hash;
}

std::string HeightfieldHasher::hex() const {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(hash_));
  return text;
}

}  // namespace aal
