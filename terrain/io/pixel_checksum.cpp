#include "aperture/terrain/io/pixel_checksum.h"

#include <xxhash.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <system_error>

namespace aal {

uint64_t xxh64(const void* data, size_t bytes, uint64_t seed) {
  return XXH64(data, bytes, seed);
}

PixelChecksum::PixelChecksum(int rows)
    : added_(static_cast<size_t>(std::max(rows, 0)), false), missing_(added_.size()) {}

void PixelChecksum::addRowHash(int row, uint64_t hash) {
  const size_t i = static_cast<size_t>(row);
  if (i >= added_.size() || added_[i]) return;
  added_[i] = true;
  --missing_;
  sum_ += hash;
}

std::string checksumHex(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(value));
  return text;
}

std::optional<uint64_t> parseChecksumHex(const std::string& text) {
  uint64_t value = 0;
  const char* end = text.data() + text.size();
  const auto [stop, error] = std::from_chars(text.data(), end, value, 16);
  if (text.size() != 16 || error != std::errc() || stop != end) return std::nullopt;
  return value;
}

}  // namespace aal
