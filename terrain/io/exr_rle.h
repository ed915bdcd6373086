// EXR's RLE chunk compression, written here so that a chunk is packed,
// predicted and compressed in one pass on any thread: through OpenEXR's core
// library the generic packing alone cost more than Imf::OutputFile's whole
// single-threaded write (docs/performance.md).
//
// The format (OpenEXR's "File Layout", RLE_COMPRESSION): the chunk's bytes
// are reordered, the even-indexed ones first, then the odd-indexed ones;
// every byte but the first is replaced by (byte - previous byte + 128) mod
// 256; the result is coded as runs: a signed count byte c >= 0 followed by
// one byte repeated c + 1 times, or c < 0 followed by -c literal bytes. A
// chunk whose coded size is not smaller than its raw size is stored raw
// (readers tell the two apart by the size).
#pragma once

#include <cstddef>
#include <cstdint>

namespace aal {

// Coded bytes at most for n raw bytes: one count byte per 128 literals.
constexpr size_t exrRleBound(size_t n) {
  return n + n / 128 + 2;
}

// Codes the n bytes at `raw` into `out` (exrRleBound(n) bytes), using
// `scratch` (n bytes) for the reordered, predicted bytes. Returns the coded
// size; when it is not below n, `out` holds the raw bytes instead and n is
// returned.
size_t exrRleCompress(const uint8_t* raw, size_t n, uint8_t* scratch, uint8_t* out);

}  // namespace aal
