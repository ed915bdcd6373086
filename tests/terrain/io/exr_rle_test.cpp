// exrRleCompress against a decoder written from the format's description
// (exr_rle.h): runs and literals of every length around the 128-byte limits,
// odd sizes, and data that does not compress (stored raw).
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "aperture/terrain/io/exr_rle.h"

namespace aal {
namespace {

// The raw bytes back from a coded chunk of n raw bytes; empty when the codes
// are malformed (a count running past either end).
std::vector<uint8_t> decode(const std::vector<uint8_t>& coded, size_t n) {
  if (coded.size() == n) return coded;  // stored raw
  std::vector<uint8_t> predicted;
  for (size_t i = 0; i < coded.size();) {
    const auto count = static_cast<int8_t>(coded[i++]);
    if (count < 0) {
      for (int k = 0; k < -count; ++k) {
        if (i >= coded.size()) return {};
        predicted.push_back(coded[i++]);
      }
    } else {
      if (i >= coded.size()) return {};
      predicted.insert(predicted.end(), static_cast<size_t>(count) + 1, coded[i++]);
    }
  }
  if (predicted.size() != n) return {};
  std::vector<uint8_t> reordered(n);
  for (size_t i = 0; i < n; ++i) {
    reordered[i] =
        i == 0 ? predicted[0] : static_cast<uint8_t>(reordered[i - 1] + predicted[i] - 128);
  }
  std::vector<uint8_t> raw(n);
  const size_t half = (n + 1) / 2;
  for (size_t i = 0; i < n; ++i) raw[i] = i % 2 == 0 ? reordered[i / 2] : reordered[half + i / 2];
  return raw;
}

std::vector<uint8_t> encode(const std::vector<uint8_t>& raw) {
  std::vector<uint8_t> scratch(raw.size()), out(exrRleBound(raw.size()));
  out.resize(exrRleCompress(raw.data(), raw.size(), scratch.data(), out.data()));
  return out;
}

// Bytes whose predicted form (the differences the coder sees) is the given
// sequence of runs: the coder's input is built backwards from it.
std::vector<uint8_t> rawWithPredictedRuns(const std::vector<std::pair<size_t, uint8_t>>& runs) {
  std::vector<uint8_t> predicted;
  for (const auto& [length, value] : runs) predicted.insert(predicted.end(), length, value);
  const size_t n = predicted.size(), half = (n + 1) / 2;
  std::vector<uint8_t> reordered(n), raw(n);
  for (size_t i = 0; i < n; ++i) {
    reordered[i] =
        i == 0 ? predicted[0] : static_cast<uint8_t>(reordered[i - 1] + predicted[i] - 128);
  }
  for (size_t i = 0; i < n; ++i) raw[i] = i % 2 == 0 ? reordered[i / 2] : reordered[half + i / 2];
  return raw;
}

TEST(ExrRle, RunsAndLiteralsOfEveryLengthRoundTrip) {
  std::mt19937 random(3);
  for (size_t length : {1u, 2u, 3u, 4u, 127u, 128u, 129u, 130u, 255u, 256u, 257u, 300u}) {
    // A run of `length`, literals of `length` (no two neighbours equal),
    // then both again, so each limit is met between other codes.
    std::vector<std::pair<size_t, uint8_t>> runs;
    for (int repeat = 0; repeat < 2; ++repeat) {
      runs.push_back({length, 7});
      for (size_t k = 0; k < length; ++k) runs.push_back({1, static_cast<uint8_t>(20 + k % 50)});
    }
    const std::vector<uint8_t> raw = rawWithPredictedRuns(runs);
    const std::vector<uint8_t> coded = encode(raw);
    EXPECT_LE(coded.size(), raw.size()) << length;
    EXPECT_EQ(decode(coded, raw.size()), raw) << length;
  }
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::pair<size_t, uint8_t>> runs;
    for (int k = 0; k < 40; ++k) {
      runs.push_back(
          {1 + random() % (random() % 4 == 0 ? 300 : 4), static_cast<uint8_t>(random() % 3)});
    }
    const std::vector<uint8_t> raw = rawWithPredictedRuns(runs);
    EXPECT_EQ(decode(encode(raw), raw.size()), raw) << trial;
  }
}

TEST(ExrRle, CompressesRunsAndStoresNoiseRaw) {
  const std::vector<uint8_t> runs = rawWithPredictedRuns({{1000, 128}, {5, 9}, {1000, 128}});
  const std::vector<uint8_t> coded = encode(runs);
  EXPECT_LT(coded.size(), 40u);  // 16 runs of 128 and a few codes
  EXPECT_EQ(decode(coded, runs.size()), runs);

  std::mt19937 random(5);
  for (size_t n : {1u, 2u, 3u, 17u, 1000u, 8192u}) {
    std::vector<uint8_t> noise(n);
    for (uint8_t& b : noise) b = static_cast<uint8_t>(random());
    EXPECT_EQ(encode(noise), noise) << n;  // no smaller coded: stored raw
  }
}

}  // namespace
}  // namespace aal
