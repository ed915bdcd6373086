#include "aperture/terrain/io/declared_size_check.h"

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

#include <cpl_conv.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>

#include "aperture/terrain/errors.h"

namespace aal {

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw InputError(path + ": " + why);
}

// Bytes of the file GDAL opened (its first file), or nothing when unknown.
std::optional<uint64_t> mainFileBytes(GDALDataset& dataset) {
  char** files = dataset.GetFileList();
  VSIStatBufL stat{};
  const bool known = files != nullptr && files[0] != nullptr && VSIStatL(files[0], &stat) == 0;
  CSLDestroy(files);
  if (!known) return std::nullopt;
  return static_cast<uint64_t>(stat.st_size);
}

int bitsPerSample(GDALRasterBand& band) {
  const char* nbits = band.GetMetadataItem("NBITS", "IMAGE_STRUCTURE");
  const int bits = nbits != nullptr ? std::atoi(nbits) : 0;
  return bits > 0 ? bits : 8 * GDALGetDataTypeSizeBytes(band.GetRasterDataType());
}

// The most a TIFF codec can expand its bytes: PackBits 2 bytes into 128,
// deflate's best is 1032:1 (258-byte matches in 2 bits), LZW's 12-bit codes
// stand for at most 4096 bytes. Nothing for codecs without a small bound
// (ZSTD, LZMA, LERC) or that DEMs do not use.
std::optional<double> tiffExpansionBound(const char* compression) {
  if (compression == nullptr || std::strcmp(compression, "NONE") == 0) return 1.0;
  if (std::strcmp(compression, "PACKBITS") == 0) return 64.0;
  if (std::strcmp(compression, "DEFLATE") == 0 || std::strcmp(compression, "ZIP") == 0) {
    return 1032.0;
  }
  if (std::strcmp(compression, "LZW") == 0) return 4096.0 * 8.0 / 12.0;
  return std::nullopt;
}

[[noreturn]] void refuseDeclaredSize(const std::string& path, uint64_t declared, uint64_t held,
                                     const std::string& why) {
  refuse(path, "is truncated or corrupt: its header declares " + std::to_string(declared) +
                   " bytes of samples, but " + why + " only " + std::to_string(held) +
                   " bytes can hold");
}

// TIFF blocks must lie in the file, cannot together hold more bytes than it
// has, and cannot decode to more than their codec can expand to: a 556 kB
// file whose 46340 strips all pointed at one row claimed 8.6 GB of heights,
// and a reader filled 10 GB with copies. Sparse blocks (offset 0) hold
// nothing and cost nothing. Above a million blocks the count itself would
// cost seconds; DemSource::read's memory check still stands there.
void checkTiffBlocks(const std::string& path, GDALDataset& dataset, GDALRasterBand& band,
                     uint64_t fileBytes) {
  int blockW = 0, blockH = 0;
  band.GetBlockSize(&blockW, &blockH);
  if (blockW < 1 || blockH < 1) return;
  const int width = dataset.GetRasterXSize(), height = dataset.GetRasterYSize();
  const int64_t columns = (width + int64_t{blockW} - 1) / blockW;
  const int64_t rows = (height + int64_t{blockH} - 1) / blockH;
  if (columns * rows > 1000000) return;
  const char* interleave = dataset.GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
  const int samples =
      interleave != nullptr && std::strcmp(interleave, "PIXEL") == 0 ? dataset.GetRasterCount() : 1;
  const uint64_t rowBytes = (static_cast<uint64_t>(blockW) * samples * bitsPerSample(band) + 7) / 8;
  const bool strips = blockW == width;  // a strip ends with the image; a tile is padded
  const auto item = [&](const char* what, int64_t x, int64_t y) -> uint64_t {
    char key[64];
    std::snprintf(key, sizeof key, "%s_%lld_%lld", what, static_cast<long long>(x),
                  static_cast<long long>(y));
    const char* value = band.GetMetadataItem(key, "TIFF");
    return value != nullptr ? std::strtoull(value, nullptr, 10) : 0;
  };
  uint64_t claimed = 0, declared = 0;
  for (int64_t y = 0; y < rows; ++y) {
    for (int64_t x = 0; x < columns; ++x) {
      const uint64_t offset = item("BLOCK_OFFSET", x, y);
      if (offset == 0) continue;
      const uint64_t bytes = item("BLOCK_SIZE", x, y);
      if (offset > fileBytes || bytes > fileBytes - offset) {
        refuse(path, "is truncated or corrupt: block " + std::to_string(x) + ", " +
                         std::to_string(y) + " lies at bytes " + std::to_string(offset) + " to " +
                         std::to_string(offset + bytes) + " of a " + std::to_string(fileBytes) +
                         "-byte file");
      }
      claimed += bytes;
      const int64_t blockRows = strips ? std::min<int64_t>(blockH, height - y * blockH) : blockH;
      declared += rowBytes * static_cast<uint64_t>(blockRows);
    }
  }
  if (claimed > fileBytes) {
    refuse(path, "is corrupt: its blocks claim " + std::to_string(claimed) +
                     " bytes in all, more than the file's " + std::to_string(fileBytes) +
                     " (blocks that share bytes)");
  }
  const char* compression = dataset.GetMetadataItem("COMPRESSION", "IMAGE_STRUCTURE");
  if (const auto bound = tiffExpansionBound(compression);
      bound && static_cast<double>(declared) > *bound * static_cast<double>(claimed)) {
    refuseDeclaredSize(path, declared, static_cast<uint64_t>(*bound * claimed),
                       std::string("its ") + (compression ? compression : "uncompressed") +
                           " blocks of " + std::to_string(claimed) + " bytes");
  }
}

}  // namespace

// What a file declares must fit in what it holds: for TIFF block by block,
// for PNG at zlib's best ratio (a 225 kB PNG claimed 40000^2 samples).
void checkDeclaredSizeFitsTheFile(const std::string& path, GDALDataset& dataset,
                                  GDALRasterBand& band) {
  GDALDriver* driver = dataset.GetDriver();
  if (driver == nullptr) return;
  const std::optional<uint64_t> fileBytes = mainFileBytes(dataset);
  if (!fileBytes) return;
  const char* name = driver->GetDescription();
  if (std::strcmp(name, "GTiff") == 0) {
    checkTiffBlocks(path, dataset, band, *fileBytes);
  } else if (std::strcmp(name, "PNG") == 0) {
    const uint64_t declared = static_cast<uint64_t>(dataset.GetRasterYSize()) *
                              ((static_cast<uint64_t>(dataset.GetRasterXSize()) *
                                    dataset.GetRasterCount() * bitsPerSample(band) +
                                7) /
                               8);
    if (static_cast<double>(declared) > 1032.0 * static_cast<double>(*fileBytes)) {
      refuseDeclaredSize(
          path, declared, 1032 * *fileBytes,
          "at zlib's best ratio (1032:1) its " + std::to_string(*fileBytes) + " bytes of file");
    }
  }
}

}  // namespace aal
