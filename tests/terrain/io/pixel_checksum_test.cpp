// The aperture map's pixel checksum (terrain/io/pixel_checksum.h): XXH64 as
// published, summed over rows in any order.
#include "aperture/terrain/io/pixel_checksum.h"

#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

namespace aal {
namespace {

TEST(PixelChecksum, Xxh64MatchesThePublishedValues) {
  EXPECT_EQ(xxh64("", 0, 0), 0xEF46DB3751D8E999ull);
  EXPECT_EQ(xxh64("a", 1, 0), 0xD24EC4F1A98C6E5Bull);
  EXPECT_EQ(xxh64("abc", 3, 0), 0x44BC2CF5AD770999ull);
  const char* text = "Nobody inspects the spammish repetition";  // 39 bytes: every tail
  EXPECT_EQ(xxh64(text, std::strlen(text), 0), 0xFBCEA83C8A378BF1ull);
}

TEST(PixelChecksum, RowsAddUpInAnyOrderOnce) {
  std::vector<std::string> rows = {"first row", "second row", "third row of bytes"};
  PixelChecksum inOrder(3), shuffled(3);
  for (int row = 0; row < 3; ++row) inOrder.addRow(row, rows[row].data(), rows[row].size());
  EXPECT_TRUE(inOrder.complete());
  for (int row : {2, 0, 2, 1}) {
    EXPECT_FALSE(shuffled.complete());
    shuffled.addRow(row, rows[row].data(), rows[row].size());
  }
  EXPECT_TRUE(shuffled.complete());
  EXPECT_EQ(inOrder.value(), shuffled.value());
  // The same bytes in other rows differ: the row number is the seed.
  PixelChecksum swapped(3);
  swapped.addRow(0, rows[1].data(), rows[1].size());
  swapped.addRow(1, rows[0].data(), rows[0].size());
  swapped.addRow(2, rows[2].data(), rows[2].size());
  EXPECT_NE(swapped.value(), inOrder.value());
}

TEST(PixelChecksum, HexRoundTrips) {
  EXPECT_EQ(checksumHex(0x0123456789abcdefull), "0123456789abcdef");
  EXPECT_EQ(parseChecksumHex("0123456789ABCDEF"), 0x0123456789abcdefull);
  EXPECT_FALSE(parseChecksumHex("0123456789abcde").has_value());
  EXPECT_FALSE(parseChecksumHex("0123456789abcdeg").has_value());
  EXPECT_FALSE(parseChecksumHex("").has_value());
}

}  // namespace
}  // namespace aal
