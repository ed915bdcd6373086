#include "aperture/terrain/io/exr_scanline_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <stdexcept>

#include <OpenEXR/openexr.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "aperture/terrain/io/exr_rle.h"
#include "aperture/terrain/io/half_floats.h"

namespace aal {

namespace {

// Where the library's writes go: the file, through a buffer, so that the
// chunks of a block (a scanline each for RLE: 1024 at 1024 rows) reach the
// kernel in a few large writes instead of one pwrite each (7 us apiece
// here). Also the library's own message for the last failure.
struct OutputSink {
  int fd = -1;
  std::vector<uint8_t> buffer;
  uint64_t bufferStart = 0;  // file offset of buffer[0]
  int writeErrno = 0;        // of the first failed write
  std::mutex errorMutex;     // the error handler runs on whichever thread failed
  std::string lastError;

  // Small enough to stay in the cache: a larger buffer is new memory whose
  // page faults cost more than the writes it saves (on this project's VMs).
  static constexpr size_t kCapacity = size_t{256} << 10;

  bool writeAt(const void* bytes, size_t size, uint64_t offset) {
    const auto* from = static_cast<const uint8_t*>(bytes);
    while (size > 0) {
      const ssize_t written = ::pwrite(fd, from, size, static_cast<off_t>(offset));
      if (written < 0 && errno == EINTR) continue;
      if (written <= 0) {
        writeErrno = written < 0 ? errno : EIO;
        return false;
      }
      from += written;
      size -= static_cast<size_t>(written);
      offset += static_cast<uint64_t>(written);
    }
    return true;
  }

  bool flush() {
    const bool ok = writeAt(buffer.data(), buffer.size(), bufferStart);
    bufferStart += buffer.size();
    buffer.clear();
    return ok;
  }

  // Appends when the write continues the buffered bytes; else writes them out
  // first (the chunk table at the end goes back to the start of the file).
  bool write(const void* bytes, size_t size, uint64_t offset) {
    if (offset != bufferStart + buffer.size() || buffer.size() + size > kCapacity) {
      if (!flush()) return false;
      bufferStart = offset;
    }
    if (size > kCapacity) {
      bufferStart = offset + size;
      return writeAt(bytes, size, offset);
    }
    const auto* from = static_cast<const uint8_t*>(bytes);
    buffer.insert(buffer.end(), from, from + size);
    return true;
  }

  void close() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }
};

void recordError(exr_const_context_t context, exr_result_t, const char* message) {
  void* user = nullptr;
  if (exr_get_user_data(context, &user) != EXR_ERR_SUCCESS || user == nullptr) return;
  auto* sink = static_cast<OutputSink*>(user);
  std::lock_guard<std::mutex> lock(sink->errorMutex);
  sink->lastError = message ? message : "";
}

int64_t writeToSink(exr_const_context_t context, void* user, const void* bytes, uint64_t size,
                    uint64_t offset, exr_stream_error_func_ptr_t error) {
  auto* sink = static_cast<OutputSink*>(user);
  if (!sink->write(bytes, size, offset)) {
    return error(context, EXR_ERR_WRITE_IO, "%s", std::strerror(sink->writeErrno)), -1;
  }
  return static_cast<int64_t>(size);
}

// The writer's state, defined here so that the helpers below can take it.
struct WriterState {
  std::string path;
  int width = 0, height = 0;
  std::array<const char*, 4> channels{};
  bool halfFloat = true;
  MapCompression compression = MapCompression::Rle;
  // Indices into `channels` in the file's (sorted) channel order.
  std::array<size_t, 4> fileOrder{};
  exr_context_t context = nullptr;
  int part = 0;
  int rowsPerChunk = 1;
  int nextRow = 0;
  OutputSink sink;

  WriterState() = default;
  WriterState(const WriterState&) = delete;
  WriterState& operator=(const WriterState&) = delete;
  // Closes a file left unfinished (a failed or interrupted write).
  ~WriterState() {
    if (context != nullptr) exr_finish(&context);
    sink.close();
  }

  void check(exr_result_t result, const char* what) {
    if (result == EXR_ERR_SUCCESS) return;
    std::string detail;
    {
      std::lock_guard<std::mutex> lock(sink.errorMutex);
      detail = sink.lastError.empty() ? exr_get_default_error_message(result) : sink.lastError;
    }
    throw std::runtime_error("cannot write " + path + " (" + what + "): " + detail);
  }
};

exr_compression_t coreCompression(MapCompression compression) {
  switch (compression) {
    case MapCompression::Rle: return EXR_COMPRESSION_RLE;
    case MapCompression::Zip: return EXR_COMPRESSION_ZIP;
    case MapCompression::None: break;
  }
  return EXR_COMPRESSION_NONE;
}

// The encoder's last step, in place of the library's own write: keeps the
// chunk's bytes (compressed, or packed when compression gained nothing or is
// off) so that the chunks of a block are written in order afterwards.
exr_result_t keepChunk(exr_encode_pipeline_t* encoder) {
  auto* chunk = static_cast<std::vector<uint8_t>*>(encoder->encoding_user_data);
  const auto* bytes = static_cast<const uint8_t*>(encoder->compressed_buffer);
  chunk->assign(bytes, bytes + encoder->compressed_bytes);
  return EXR_ERR_SUCCESS;
}

using ChunkRange = tbb::blocked_range<int>;

// Chunks `range` of the block at `rows` (one row each, RLE or none), packed
// as the file stores them: each row's channels one after the other in the
// file's order, halves or floats, little-endian as this machine; RLE-coded.
void packRows(const WriterState& s, const float* rows, const ChunkRange& range,
              std::vector<std::vector<uint8_t>>& chunks) {
  const size_t width = static_cast<size_t>(s.width);
  const size_t component = s.halfFloat ? 2 : 4;
  const size_t rowBytes = 4 * component * width;
  std::vector<float> channel(width);
  std::vector<uint8_t> packed(rowBytes), scratch(rowBytes), coded(exrRleBound(rowBytes));
  for (int c = range.begin(); c < range.end(); ++c) {
    const float* row = rows + static_cast<size_t>(c) * 4 * width;
    uint8_t* to = packed.data();
    for (const size_t k : s.fileOrder) {
      for (size_t x = 0; x < width; ++x) channel[x] = row[4 * x + k];
      if (s.halfFloat) {
        floatsToHalves(channel.data(), reinterpret_cast<uint16_t*>(to), width);
      } else {
        std::memcpy(to, channel.data(), 4 * width);
      }
      to += component * width;
    }
    std::vector<uint8_t>& chunk = chunks[static_cast<size_t>(c)];
    if (s.compression == MapCompression::Rle) {
      const size_t size = exrRleCompress(packed.data(), rowBytes, scratch.data(), coded.data());
      chunk.assign(coded.begin(), coded.begin() + static_cast<std::ptrdiff_t>(size));
    } else {
      chunk = packed;
    }
  }
}

// Chunks `range` of the block that starts at `firstRow`, encoded by the core
// library's pipeline (ZIP: zlib dominates, and the chunks are 16 rows).
void encodeWithCore(const WriterState& s, const float* rows, int firstRow, const ChunkRange& range,
                    std::vector<std::vector<uint8_t>>& chunks, std::vector<exr_result_t>& results) {
  const size_t componentBytes = s.halfFloat ? 2 : 4;
  const size_t texelBytes = 4 * componentBytes;
  const size_t rowBytes = texelBytes * static_cast<size_t>(s.width);
  const size_t rowFloats = 4 * static_cast<size_t>(s.width);
  // A chunk's rows as halves, converted as packRows converts them.
  std::vector<uint16_t> halves(s.halfFloat ? rowFloats * static_cast<size_t>(s.rowsPerChunk) : 0);
  exr_encode_pipeline_t encoder = EXR_ENCODE_PIPELINE_INITIALIZER;
  bool initialised = false;
  for (int c = range.begin(); c < range.end(); ++c) {
    const int y = firstRow + c * s.rowsPerChunk;
    exr_chunk_info_t info{};
    exr_result_t result = exr_write_scanline_chunk_info(s.context, s.part, y, &info);
    if (result == EXR_ERR_SUCCESS) {
      result = initialised ? exr_encoding_update(s.context, s.part, &info, &encoder)
                           : exr_encoding_initialize(s.context, s.part, &info, &encoder);
      initialised = initialised || result == EXR_ERR_SUCCESS;
    }
    if (result == EXR_ERR_SUCCESS) {
      const float* chunkFloats = rows + static_cast<size_t>(y - firstRow) * rowFloats;
      const auto* chunkRows = reinterpret_cast<const uint8_t*>(chunkFloats);
      if (s.halfFloat) {
        floatsToHalves(chunkFloats, halves.data(), static_cast<size_t>(info.height) * rowFloats);
        chunkRows = reinterpret_cast<const uint8_t*>(halves.data());
      }
      for (int k = 0; k < encoder.channel_count; ++k) {
        exr_coding_channel_info_t& channel = encoder.channels[k];
        const auto named = std::find_if(s.channels.begin(), s.channels.end(), [&](const char* n) {
          return std::strcmp(n, channel.channel_name) == 0;
        });
        channel.encode_from_ptr =
            chunkRows + static_cast<size_t>(named - s.channels.begin()) * componentBytes;
        channel.user_bytes_per_element = int16_t(componentBytes);
        channel.user_data_type = s.halfFloat ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT;
        channel.user_pixel_stride = int32_t(texelBytes);
        channel.user_line_stride = int32_t(rowBytes);
      }
      result = exr_encoding_choose_default_routines(s.context, s.part, &encoder);
    }
    if (result == EXR_ERR_SUCCESS) {
      encoder.yield_until_ready_fn = nullptr;  // chunks are written in order afterwards
      encoder.write_fn = keepChunk;
      encoder.encoding_user_data = &chunks[static_cast<size_t>(c)];
      result = exr_encoding_run(s.context, s.part, &encoder);
    }
    results[static_cast<size_t>(c)] = result;
    if (result != EXR_ERR_SUCCESS) break;
  }
  if (initialised) exr_encoding_destroy(s.context, &encoder);
}

}  // namespace

struct ExrScanlineWriter::State : WriterState {};

ExrScanlineWriter::ExrScanlineWriter(const std::string& path, int width, int height,
                                     const std::array<const char*, 4>& channels, bool halfFloat,
                                     MapCompression compression,
                                     const std::vector<ExrAttribute>& attributes)
    : state_(std::make_unique<State>()) {
  State& s = *state_;
  s.path = path;
  s.width = width;
  s.height = height;
  s.channels = channels;
  s.halfFloat = halfFloat;
  s.compression = compression;
  for (size_t c = 0; c < 4; ++c) s.fileOrder[c] = c;
  std::sort(s.fileOrder.begin(), s.fileOrder.end(),
            [&](size_t a, size_t b) { return std::strcmp(channels[a], channels[b]) < 0; });
  if (width <= 0 || height <= 0) {
    throw std::invalid_argument("cannot write " + path + ": an EXR of " + std::to_string(width) +
                                " x " + std::to_string(height) + " texels");
  }
  s.sink.buffer.reserve(OutputSink::kCapacity);
  s.sink.fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (s.sink.fd < 0) {
    throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
  }
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  init.error_handler_fn = recordError;
  init.user_data = &s.sink;
  init.write_fn = writeToSink;
  s.check(exr_start_write(&s.context, path.c_str(), EXR_WRITE_FILE_DIRECTLY, &init), "create");
  s.check(exr_add_part(s.context, nullptr, EXR_STORAGE_SCANLINE, &s.part), "part");
  s.check(exr_initialize_required_attr_simple(s.context, s.part, width, height,
                                              coreCompression(compression)),
          "header");
  if (compression == MapCompression::Zip) {
    // Imf::Header's default level; the core library's own (-1) is zlib's 6,
    // slower for a file a few per cent smaller.
    s.check(exr_set_zip_compression_level(s.context, s.part, 4), "header");
  }
  for (const char* name : channels) {
    // exr_add_channel returns the library's result code, as the other calls.
    s.check(exr_result_t(exr_add_channel(s.context, s.part, name,
                                         halfFloat ? EXR_PIXEL_HALF : EXR_PIXEL_FLOAT,
                                         EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1)),
            "channel");
  }
  for (const ExrAttribute& a : attributes) {
    const char* name = a.name.c_str();
    exr_result_t result = EXR_ERR_SUCCESS;
    if (const int* i = std::get_if<int>(&a.value)) {
      result = exr_attr_set_int(s.context, s.part, name, *i);
    } else if (const float* f = std::get_if<float>(&a.value)) {
      result = exr_attr_set_float(s.context, s.part, name, *f);
    } else {
      result = exr_attr_set_string(s.context, s.part, name, std::get<std::string>(a.value).c_str());
    }
    s.check(result, name);
  }
  s.check(exr_write_header(s.context), "header");
  int32_t rows = 1;
  s.check(exr_get_scanlines_per_chunk(s.context, s.part, &rows), "header");
  s.rowsPerChunk = std::max(1, int(rows));
}

ExrScanlineWriter::~ExrScanlineWriter() = default;

int ExrScanlineWriter::rowsPerChunk() const {
  return state_->rowsPerChunk;
}

void ExrScanlineWriter::writeRows(const float* rows, int firstRow, int endRow) {
  State& s = *state_;
  if (firstRow != s.nextRow || endRow <= firstRow || endRow > s.height ||
      (endRow < s.height && (endRow - firstRow) % s.rowsPerChunk != 0)) {
    throw std::logic_error("ExrScanlineWriter: rows " + std::to_string(firstRow) + ".." +
                           std::to_string(endRow) + " out of order or not whole chunks");
  }
  const int chunkCount = (endRow - firstRow + s.rowsPerChunk - 1) / s.rowsPerChunk;
  std::vector<std::vector<uint8_t>> chunks(static_cast<size_t>(chunkCount));
  std::vector<exr_result_t> results(static_cast<size_t>(chunkCount), EXR_ERR_SUCCESS);
  // Chunks are small (8 KiB for RLE at 1024 columns): several per task.
  tbb::parallel_for(tbb::blocked_range<int>(0, chunkCount, 8),
                    [&](const tbb::blocked_range<int>& range) {
                      if (s.compression == MapCompression::Zip) {
                        encodeWithCore(s, rows, firstRow, range, chunks, results);
                      } else {
                        packRows(s, rows, range, chunks);
                      }
                    });
  for (int c = 0; c < chunkCount; ++c) {
    s.check(results[static_cast<size_t>(c)], "compressing");
  }
  for (int c = 0; c < chunkCount; ++c) {
    const std::vector<uint8_t>& chunk = chunks[static_cast<size_t>(c)];
    s.check(exr_write_scanline_chunk(s.context, s.part, firstRow + c * s.rowsPerChunk, chunk.data(),
                                     chunk.size()),
            "writing");
  }
  s.nextRow = endRow;
}

void ExrScanlineWriter::finish() {
  State& s = *state_;
  if (s.nextRow != s.height) {
    throw std::logic_error("ExrScanlineWriter: finished after " + std::to_string(s.nextRow) +
                           " of " + std::to_string(s.height) + " rows");
  }
  exr_context_t context = s.context;
  s.context = nullptr;
  s.check(exr_finish(&context), "closing");
  const bool flushed = s.sink.flush();
  const int closed = ::close(s.sink.fd);
  s.sink.fd = -1;
  if (!flushed || closed != 0) {
    throw std::runtime_error("cannot write " + s.path + ": " +
                             std::strerror(flushed ? errno : s.sink.writeErrno));
  }
}

}  // namespace aal
