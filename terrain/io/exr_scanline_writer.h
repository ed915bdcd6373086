// Scanline EXR files whose chunks are compressed on every core, through
// OpenEXR's C "core" API (chunks encoded on any thread, written in order).
// Imf::OutputFile runs one task per chunk, and an RLE chunk is one scanline
// (8 KiB at 1024 columns of four halves): its thread pool wrote a 1024² map
// no faster on two threads than on one (docs/performance.md). Here a block of
// rows is encoded on oneTBB's threads, several chunks per task, and its
// chunks are then written in order.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <variant>
#include <vector>

#include "aperture/terrain/io/map_compression.h"

namespace aal {

struct ExrAttribute {
  std::string name;
  std::variant<int, float, std::string> value;
};

class ExrScanlineWriter {
 public:
  // Creates `path` (replacing it) and writes the header: width x height
  // texels of the four `channels` (the file stores them sorted by name, as
  // every EXR writer does), each a half or a float, and `attributes`. Throws
  // std::runtime_error naming the path when the file cannot be written.
  ExrScanlineWriter(const std::string& path, int width, int height,
                    const std::array<const char*, 4>& channels, bool halfFloat,
                    MapCompression compression, const std::vector<ExrAttribute>& attributes);
  ~ExrScanlineWriter();
  ExrScanlineWriter(const ExrScanlineWriter&) = delete;
  ExrScanlineWriter& operator=(const ExrScanlineWriter&) = delete;

  // Rows of one chunk: 1 for RLE and none, 16 for ZIP.
  int rowsPerChunk() const;

  // Writes rows [firstRow, endRow) from `rows`: texels of four floats, the
  // channels in `channels` order, rows back to back; stored as halves
  // (floatsToHalves: round to nearest even, as Imath) or floats. Rows come in
  // order, each call starting where the last one ended, and every call but
  // the last covers whole chunks.
  void writeRows(const float* rows, int firstRow, int endRow);

  // Writes the chunk offset table and closes the file; every row must have
  // been written. Without finish(), the destructor closes an incomplete file
  // (its caller removes it).
  void finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace aal
