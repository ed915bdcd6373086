#include "aperture/terrain/io/exr_rle.h"

#include <algorithm>
#include <cstring>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace aal {
namespace {

constexpr size_t kMaxRun = 128;      // a count byte c in 0..127 repeats c + 1 times
constexpr size_t kMaxLiteral = 128;  // a count byte -c, c in 1..128, copies c bytes

// Where the first run worth coding (three equal bytes: shorter repeats cost
// as much as literals) starts in bytes[from, n), or n when there is none.
size_t nextRunStart(const uint8_t* bytes, size_t from, size_t n) {
  size_t i = from;
#if defined(__SSE2__)
  // Sixteen positions at a time: the noisy low bytes of a map's halves hold
  // few runs, and this search is most of the coder's time.
  for (; i + 18 <= n; i += 16) {
    const __m128i a = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i));
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i + 1));
    const __m128i c = _mm_loadu_si128(reinterpret_cast<const __m128i*>(bytes + i + 2));
    const int starts = _mm_movemask_epi8(_mm_and_si128(_mm_cmpeq_epi8(a, b), _mm_cmpeq_epi8(b, c)));
    if (starts != 0) return i + static_cast<size_t>(__builtin_ctz(static_cast<unsigned>(starts)));
  }
#endif
  for (; i + 2 < n; ++i) {
    if (bytes[i] == bytes[i + 1] && bytes[i + 1] == bytes[i + 2]) return i;
  }
  return n;
}

// Length of the run of equal bytes starting at `at`, at most kMaxRun.
size_t runLength(const uint8_t* bytes, size_t at, size_t n) {
  const size_t end = std::min(n, at + kMaxRun);
  size_t i = at + 1;
  while (i < end && bytes[i] == bytes[at]) ++i;
  return i - at;
}

}  // namespace

size_t exrRleCompress(const uint8_t* raw, size_t n, uint8_t* scratch, uint8_t* out) {
  if (n == 0) return 0;
  // Even bytes, then odd bytes (for halves: low bytes, then high bytes),
  // each replaced by its difference to the byte before it in that order.
  const size_t half = (n + 1) / 2;
  scratch[0] = raw[0];
  for (size_t i = 1; i < half; ++i) {
    scratch[i] = static_cast<uint8_t>(raw[2 * i] - raw[2 * i - 2] + 128);
  }
  if (n > 1) scratch[half] = static_cast<uint8_t>(raw[1] - raw[2 * half - 2] + 128);
  for (size_t i = 1; half + i < n; ++i) {
    scratch[half + i] = static_cast<uint8_t>(raw[2 * i + 1] - raw[2 * i - 1] + 128);
  }
  size_t coded = 0;
  size_t i = 0;
  while (i < n && coded < n) {
    const size_t run = nextRunStart(scratch, i, n);
    while (i < run && coded < n) {
      const size_t literals = std::min(kMaxLiteral, run - i);
      out[coded++] = static_cast<uint8_t>(-static_cast<int>(literals));
      std::memcpy(out + coded, scratch + i, literals);
      coded += literals;
      i += literals;
    }
    if (run == n || coded >= n) break;
    const size_t length = runLength(scratch, run, n);
    out[coded++] = static_cast<uint8_t>(length - 1);
    out[coded++] = scratch[run];
    i = run + length;
  }
  if (coded >= n) {  // no smaller than raw: stored raw
    std::memcpy(out, raw, n);
    return n;
  }
  return coded;
}

}  // namespace aal
