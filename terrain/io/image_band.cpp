#include "image_band.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <memory>
#include <type_traits>
#include <vector>

#include <OpenImageIO/imageio.h>

#include "errors.h"

namespace aal {

namespace {

// Texels read per chunk: bounds the temporary buffer of native samples.
constexpr size_t kChunkTexels = size_t{1} << 22;

// OpenImageIO's message, first line only (a corrupt file gives one per strip).
std::string oneLine(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  if (text.empty()) return "unknown error";
  const size_t more = static_cast<size_t>(std::count(text.begin(), text.end(), '\n'));
  if (more == 0) return text;
  return text.substr(0, text.find('\n')) + " (and " + std::to_string(more) + " more)";
}

// Matches the nodata value in the sample's own type, so that a float32
// nodata written as a decimal string still matches exactly.
template <typename T>
struct NodataMatcher {
  bool active = false;
  T value{};
  bool operator()(T sample) const { return active && sample == value; }
};

template <typename T>
NodataMatcher<T> makeNodataMatcher(std::optional<double> nodata) {
  if (!nodata || std::isnan(*nodata)) return {};
  if constexpr (std::is_integral_v<T>) {
    const double v = *nodata;
    if (v != std::trunc(v) || v < static_cast<double>(std::numeric_limits<T>::lowest()) ||
        v > static_cast<double>(std::numeric_limits<T>::max())) {
      return {};  // can never match an integer sample
    }
    return {true, static_cast<T>(v)};
  } else {
    return {true, static_cast<T>(*nodata)};
  }
}

template <typename T>
void convertSamples(const std::vector<std::byte>& buffer, size_t count, size_t firstIndex,
                    std::optional<double> nodata, RawDem& dem) {
  const NodataMatcher<T> isNodata = makeNodataMatcher<T>(nodata);
  for (size_t i = 0; i < count; ++i) {
    T sample;
    std::memcpy(&sample, buffer.data() + i * sizeof(T), sizeof(T));
    if (isNodata(sample)) {
      dem.voidMask[firstIndex + i] = 1;
    } else {
      storeSample(dem, firstIndex + i, static_cast<double>(sample));
    }
  }
}

using Converter = void (*)(const std::vector<std::byte>&, size_t, size_t, std::optional<double>,
                           RawDem&);

struct SampleReading {
  OIIO::TypeDesc readAs;  // type handed to OpenImageIO
  Converter convert;
  const char* name;
};

// Integers are read natively; half and float as float (an exact, unscaled
// conversion); double as double.
std::optional<SampleReading> sampleReading(OIIO::TypeDesc type) {
  switch (type.basetype) {
    case OIIO::TypeDesc::UINT8: return SampleReading{type, convertSamples<uint8_t>, "uint8"};
    case OIIO::TypeDesc::INT8: return SampleReading{type, convertSamples<int8_t>, "int8"};
    case OIIO::TypeDesc::UINT16: return SampleReading{type, convertSamples<uint16_t>, "uint16"};
    case OIIO::TypeDesc::INT16: return SampleReading{type, convertSamples<int16_t>, "int16"};
    case OIIO::TypeDesc::UINT32: return SampleReading{type, convertSamples<uint32_t>, "uint32"};
    case OIIO::TypeDesc::INT32: return SampleReading{type, convertSamples<int32_t>, "int32"};
    case OIIO::TypeDesc::HALF:
      return SampleReading{OIIO::TypeDesc::FLOAT, convertSamples<float>, "float16"};
    case OIIO::TypeDesc::FLOAT:
      return SampleReading{OIIO::TypeDesc::FLOAT, convertSamples<float>, "float32"};
    case OIIO::TypeDesc::DOUBLE:
      return SampleReading{OIIO::TypeDesc::DOUBLE, convertSamples<double>, "float64"};
    default: return std::nullopt;
  }
}

std::string channelList(const OIIO::ImageSpec& spec) {
  std::string list;
  for (int c = 0; c < spec.nchannels && c < static_cast<int>(spec.channelnames.size()); ++c) {
    if (!list.empty()) list += ", ";
    list += spec.channelnames[static_cast<size_t>(c)];
  }
  return list;
}

// Rows per chunk: whole tile rows for tiled files (read_tiles needs tile
// alignment; OpenImageIO 2.4's read_scanlines crashes on tiled TIFFs).
int chunkRows(const OIIO::ImageSpec& spec) {
  int rows = static_cast<int>(
      std::max<size_t>(1, kChunkTexels / static_cast<size_t>(std::max(spec.width, 1))));
  if (spec.tile_width > 0 && spec.tile_height > 0) {
    rows = std::max(1, rows / spec.tile_height) * spec.tile_height;
  }
  return std::min(rows, spec.height);
}

}  // namespace

RawDem readImageBand(const std::string& path, const std::string& oiioFormat,
                     std::optional<double> nodata, const DemLoadOptions& options) {
  std::unique_ptr<OIIO::ImageInput> in = OIIO::ImageInput::create(oiioFormat);
  if (!in) {
    throw std::runtime_error("OpenImageIO has no " + oiioFormat +
                             " reader: " + oneLine(OIIO::geterror()));
  }
  OIIO::ImageSpec spec;
  const OIIO::ImageSpec config;
  if (!in->open(path, spec, config)) {
    throw InputError(path + ": cannot read as " + oiioFormat + ": " + oneLine(in->geterror()));
  }
  if (spec.depth > 1) throw InputError(path + ": volume images are not DEMs");
  if (spec.nchannels < 1) throw InputError(path + ": image has no channels");
  checkDemSize(path, spec.width, spec.height, options.maxTexels);

  const OIIO::TypeDesc type = spec.channelformat(0);
  const std::optional<SampleReading> reading = sampleReading(type);
  if (!reading) {
    throw InputError(path + ": sample type " + std::string(type.c_str()) + " is not supported");
  }
  if (spec.nchannels > 1 && options.warn) {
    options.warn(path + " has " + std::to_string(spec.nchannels) + " channels (" +
                 channelList(spec) + "); using the first one (" +
                 (spec.channelnames.empty() ? std::string("1") : spec.channelnames[0]) +
                 ") as heights");
  }

  RawDem dem;
  dem.sampleType = reading->name;
  dem.allocate(spec.width, spec.height);
  const int rowsPerChunk = chunkRows(spec);
  const size_t sampleBytes = reading->readAs.size();
  std::vector<std::byte> buffer(static_cast<size_t>(rowsPerChunk) *
                                static_cast<size_t>(spec.width) * sampleBytes);
  for (int row = 0; row < spec.height; row += rowsPerChunk) {
    const int rows = std::min(rowsPerChunk, spec.height - row);
    const bool ok =
        spec.tile_width > 0
            ? in->read_tiles(0, 0, spec.x, spec.x + spec.width, spec.y + row, spec.y + row + rows,
                             spec.z, spec.z + 1, 0, 1, reading->readAs, buffer.data())
            : in->read_scanlines(0, 0, spec.y + row, spec.y + row + rows, spec.z, 0, 1,
                                 reading->readAs, buffer.data());
    // OpenImageIO 2.4 may return true from a read that libtiff failed (a
    // truncated strip, corrupt deflate data) and only leave the message.
    const std::string error = in->geterror();
    if (!ok || !error.empty()) {
      throw InputError(path + ": cannot decode rows " + std::to_string(row) + ".." +
                       std::to_string(row + rows - 1) +
                       " (truncated or corrupt?): " + oneLine(error));
    }
    reading->convert(buffer, static_cast<size_t>(rows) * static_cast<size_t>(spec.width),
                     static_cast<size_t>(row) * static_cast<size_t>(spec.width), nodata, dem);
  }
  return dem;
}

}  // namespace aal
