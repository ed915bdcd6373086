// libFuzzer target: SRTM .hgt parser. Input: one byte n, an n-byte file name
// (n % 32), one flag byte, then the file. With the flag 'T' the file bytes
// are repeated to the size of a 1201 x 1201 tile, so that decoding, voids and
// georeferencing are reached, not only the size check. (Filling and the rest
// of loading are fuzzed through fuzz_ascii_grid, where grids are small.)
#include <algorithm>
#include <cstdlib>
#include <string>
#include <vector>

#include "errors.h"
#include "fuzz_common.h"
#include "hgt_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const size_t nameLength = std::min<size_t>(data[0] % 32, size - 2);
  const std::string name(reinterpret_cast<const char*>(data + 1), nameLength);
  const uint8_t flags = data[1 + nameLength];
  std::vector<uint8_t> bytes(data + 2 + nameLength, data + size);
  if (flags == 'T' && !bytes.empty()) {
    const size_t tileBytes = 1201u * 1201u * 2u;
    std::vector<uint8_t> tile(tileBytes);
    for (size_t i = 0; i < tileBytes; ++i) tile[i] = bytes[i % bytes.size()];
    bytes.swap(tile);
  }
  const aal::DemLoadOptions options = aal::fuzz::options();
  try {
    const aal::RawDem dem = aal::parseHgt(name, bytes, options);
    // Every void sample, and only those, is flagged.
    for (size_t i = 0; i < dem.texelCount(); ++i) {
      const bool isVoid = bytes[2 * i] == 0x80 && bytes[2 * i + 1] == 0x00;
      if (isVoid != (dem.voidMask[i] != 0)) std::abort();
    }
  } catch (const aal::InputError&) {
  }
  return 0;
}
