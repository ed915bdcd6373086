#include "png_header.h"

#include <cstdint>
#include <filesystem>
#include <fstream>

#include "errors.h"
#include "raw_dem.h"

namespace aal {

namespace {

// PNG specification (ISO/IEC 15948), section 5: an 8-byte signature, then
// chunks of a big-endian length, a 4-letter type, the data and a CRC.
constexpr uint32_t kMaxChunkLength = 0x7fffffffu;

uint32_t bigEndian32(const unsigned char* b) {
  return uint32_t{b[0]} << 24 | uint32_t{b[1]} << 16 | uint32_t{b[2]} << 8 | uint32_t{b[3]};
}

}  // namespace

void checkPngStructure(const std::string& path, const DemLoadOptions& options) {
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (error) throw InputError(path + ": cannot read: " + error.message());
  std::ifstream in(path, std::ios::binary);
  const auto fail = [&](const std::string& problem) {
    throw InputError(path + ": corrupt or truncated PNG: " + problem);
  };
  uintmax_t position = 8;
  in.seekg(8);
  bool first = true;
  for (;;) {
    unsigned char head[8];
    if (size - position < 12 || !in.read(reinterpret_cast<char*>(head), 8)) {
      fail("it ends before the IEND chunk");
    }
    const uint32_t length = bigEndian32(head);
    const std::string type(reinterpret_cast<const char*>(head + 4), 4);
    if (length > kMaxChunkLength || length > size - position - 12) {
      fail("chunk '" + type + "' of " + std::to_string(length) +
           " bytes runs past the end of the file");
    }
    if (first) {
      if (type != "IHDR" || length != 13) fail("the first chunk is not IHDR");
      unsigned char ihdr[8];
      if (!in.read(reinterpret_cast<char*>(ihdr), 8)) fail("IHDR ends early");
      checkDemSize(path, bigEndian32(ihdr), bigEndian32(ihdr + 4), options.maxTexels);
      in.seekg(static_cast<std::streamoff>(length - 8 + 4), std::ios::cur);
      first = false;
    } else {
      in.seekg(static_cast<std::streamoff>(length) + 4, std::ios::cur);
    }
    position += 12 + uintmax_t{length};
    if (type == "IEND") return;
  }
}

}  // namespace aal
