// The checksum of an aperture map's pixels (aal:pixelChecksum, docs/baking.md):
// the sum, modulo 2^64, over rows of XXH64(the row's bytes as stored in the
// file, seed = the row's number). A sum of per-row hashes lets a reader
// verify rows in whatever order and bands it reads them, and the row number
// as seed makes swapped rows differ.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace aal {

// XXH64 (xxhash.com's 64-bit hash, Debian's libxxhash) of `bytes` bytes.
uint64_t xxh64(const void* data, size_t bytes, uint64_t seed);

class PixelChecksum {
 public:
  explicit PixelChecksum(int rows);
  // What row `row` (counted from 0) adds: hashed apart, rows can be hashed
  // on several threads.
  static uint64_t rowHash(int row, const void* bytes, size_t count) {
    return xxh64(bytes, count, static_cast<uint64_t>(row));
  }
  // Adds row `row` unless it was added already.
  void addRowHash(int row, uint64_t hash);
  void addRow(int row, const void* bytes, size_t count) {
    addRowHash(row, rowHash(row, bytes, count));
  }
  // Whether every row has been added.
  bool complete() const { return missing_ == 0; }
  uint64_t value() const { return sum_; }

 private:
  std::vector<bool> added_;
  size_t missing_;
  uint64_t sum_ = 0;
};

// 16 lower-case hex digits, as the header stores it.
std::string checksumHex(uint64_t value);
// The value of 16 hex digits, or nothing when `text` is not that.
std::optional<uint64_t> parseChecksumHex(const std::string& text);

}  // namespace aal
