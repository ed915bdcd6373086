// Floats to IEEE 754 half floats, as the aperture map's writer and its pixel
// checksum store them (docs/baking.md). Rounds to nearest even, like
// Imath's imath_float_to_half; on CPUs with F16C eight at a time.
#pragma once

#include <cstddef>
#include <cstdint>

namespace aal {

// out[i] = the half nearest in[i] (ties to even; overflow to infinity), as
// bits, for i < count. Bit for bit Imath's conversion for every finite
// float and infinity; NaNs stay NaNs.
void floatsToHalves(const float* in, uint16_t* out, size_t count);

}  // namespace aal
