#include "aperture/terrain/io/half_floats.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include <Imath/half.h>
#include <gtest/gtest.h>

namespace aal {
namespace {

float fromBits(uint32_t bits) {
  float f;
  std::memcpy(&f, &bits, sizeof f);
  return f;
}

// Imath's portable conversion (this file is built without F16C): what the
// map's writer stored before the vector path existed.
uint16_t imathHalf(float f) {
  return Imath::half(f).bits();
}

TEST(HalfFloats, EveryFloatPatternOneIn97MatchesImath) {
  // Strides over all 2^32 bit patterns: every exponent, both signs, normal,
  // subnormal and overflowing halves, and ties (low 13 bits 0x1000).
  constexpr uint64_t kStride = 97;
  std::vector<float> in;
  in.reserve((uint64_t{1} << 32) / kStride / 4 + 8);
  std::vector<uint16_t> out;
  size_t mismatches = 0;
  const auto check = [&] {
    out.resize(in.size());
    floatsToHalves(in.data(), out.data(), in.size());
    for (size_t i = 0; i < in.size(); ++i) {
      if (std::isnan(in[i])) {
        const uint16_t h = out[i];
        if ((h & 0x7c00) != 0x7c00 || (h & 0x03ff) == 0) ++mismatches;  // still a NaN
      } else if (out[i] != imathHalf(in[i])) {
        if (++mismatches < 5) {
          ADD_FAILURE() << "float " << in[i] << ": half bits " << out[i] << ", Imath "
                        << imathHalf(in[i]);
        }
      }
    }
    in.clear();
  };
  for (uint64_t bits = 0; bits < (uint64_t{1} << 32); bits += kStride) {
    in.push_back(fromBits(static_cast<uint32_t>(bits)));
    if (in.size() == (size_t{1} << 22)) check();
  }
  check();
  EXPECT_EQ(mismatches, 0u);
}

TEST(HalfFloats, EdgesAndTailsMatchImath) {
  const float cases[] = {0.0f,
                         -0.0f,
                         1.0f,
                         1.5707964f,
                         65504.0f,               // the largest half
                         65519.99f,              // still rounds down to it
                         65520.0f,               // ties away to infinity
                         6.1035156e-05f,         // the smallest normal half
                         5.9604645e-08f,         // the smallest subnormal half
                         2.9802322e-08f,         // half of it: a tie, to even (0)
                         4.4703484e-08f,         // 0.75 of it: up
                         1.0f + 1.0f / 2048.0f,  // a tie between 1 and 1 + 2^-10: to even
                         std::numeric_limits<float>::infinity(),
                         -std::numeric_limits<float>::infinity(),
                         std::numeric_limits<float>::max(),
                         std::numeric_limits<float>::denorm_min()};
  // Every count from 0 to 17 from every start: the vector loop's tail too.
  std::vector<float> all(std::begin(cases), std::end(cases));
  for (size_t start = 0; start < all.size(); ++start) {
    for (size_t count = 0; start + count <= all.size(); ++count) {
      std::vector<uint16_t> out(count + 1, 0xabcd);
      floatsToHalves(all.data() + start, out.data(), count);
      for (size_t i = 0; i < count; ++i) {
        EXPECT_EQ(out[i], imathHalf(all[start + i])) << all[start + i];
      }
      EXPECT_EQ(out[count], 0xabcd) << "wrote past the end";
    }
  }
  EXPECT_EQ(imathHalf(65520.0f), 0x7c00);  // the cases mean what they say
  EXPECT_EQ(imathHalf(2.9802322e-08f), 0);
}

}  // namespace
}  // namespace aal
