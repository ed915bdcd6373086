// Files whose headers claim more than they hold, built byte by byte: the
// tests' and the fuzzers' standard oversize cases.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace aal::test {

// A classic little-endian float32 TIFF of width x height texels in strips of
// one row, strip `row` at stripOffset(row, data), where `data` is the start
// of `dataRows` rows of zeros at the file's end, each strip `stripBytes`
// long (0: a row). A header that claims gigabytes costs 8 bytes per strip.
inline std::string stripTiff(uint32_t width, uint32_t height, uint32_t dataRows,
                             const std::function<uint32_t(uint32_t, uint32_t)>& stripOffset,
                             uint32_t stripBytes = 0) {
  std::string b("II*\0", 4);
  const auto u16 = [&](uint16_t v) { b.append(reinterpret_cast<const char*>(&v), 2); };
  const auto u32 = [&](uint32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); };
  const uint32_t rowBytes = 4u * width, tags = 9;
  const uint32_t offsets = 8 + 2 + tags * 12 + 4, counts = offsets + 4u * height,
                 data = counts + 4u * height;
  const auto tag = [&](uint16_t id, uint16_t type, uint32_t count, uint32_t value) {
    u16(id), u16(type), u32(count), u32(value);  // SHORT values sit left-justified
  };
  u32(8);
  u16(tags);
  tag(256, 4, 1, width);         // ImageWidth
  tag(257, 4, 1, height);        // ImageLength
  tag(258, 3, 1, 32);            // BitsPerSample
  tag(259, 3, 1, 1);             // Compression: none
  tag(262, 3, 1, 1);             // Photometric: min is black
  tag(273, 4, height, offsets);  // StripOffsets
  tag(278, 4, 1, 1);             // RowsPerStrip
  tag(279, 4, height, counts);   // StripByteCounts
  tag(339, 3, 1, 3);             // SampleFormat: IEEE float
  u32(0);
  for (uint32_t row = 0; row < height; ++row) u32(stripOffset(row, data));
  for (uint32_t row = 0; row < height; ++row) u32(stripBytes > 0 ? stripBytes : rowBytes);
  b.append(static_cast<size_t>(rowBytes) * dataRows, '\0');
  return b;
}

// Every strip at the same row: a few bytes per strip claim width*height*4.
inline std::string sharedStripTiff(uint32_t width, uint32_t height) {
  return stripTiff(width, height, 1, [](uint32_t, uint32_t data) { return data; });
}

// CRC-32 of PNG chunks (ISO 3309), bit by bit.
inline uint32_t crc32(const std::string& bytes) {
  uint32_t crc = 0xffffffffu;
  for (const unsigned char byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xedb88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// A PNG whose header (IHDR, CRC correct) claims width x height pixels of
// `bitDepth` bits in `colourType` (0 grey, 2 RGB, ...), with `idat` as its
// only IDAT chunk.
inline std::string pngWithHeader(uint32_t width, uint32_t height, char bitDepth, char colourType,
                                 const std::string& idat) {
  std::string png = "\x89PNG\r\n\x1a\n";
  const auto be32 = [](uint32_t v) {
    return std::string{static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                       static_cast<char>(v >> 8), static_cast<char>(v)};
  };
  const auto chunk = [&](const std::string& type, const std::string& data) {
    png += be32(static_cast<uint32_t>(data.size())) + type + data + be32(crc32(type + data));
  };
  chunk("IHDR", be32(width) + be32(height) + std::string{bitDepth, colourType, 0, 0, 0});
  chunk("IDAT", idat);
  chunk("IEND", "");
  return png;
}

// A 16-bit grey PNG header claiming width x height samples, with 200 bytes
// of IDAT: far less than zlib could expand into them.
inline std::string pngClaiming(uint32_t width, uint32_t height) {
  return pngWithHeader(width, height, 16, 0, std::string(200, 'x'));
}

// An 8-bit RGB PNG header claiming width x height pixels over a tiny, valid
// zlib stream (of nothing).
inline std::string rgbPngClaiming(uint32_t width, uint32_t height) {
  return pngWithHeader(width, height, 8, 2, std::string("\x78\x9c\x03\x00\x00\x00\x00\x01", 8));
}

}  // namespace aal::test
