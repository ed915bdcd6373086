// Writes small TIFF/GeoTIFF files for the DEM tests with libtiff and
// libgeotiff directly (not through the code under test), including a
// hand-laid-out TIFF whose pixel data can be cut short.
#pragma once

#include <geotiff/geotiff.h>
#include <geotiff/xtiffio.h>
#include <tiffio.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace aal::test {

enum class SampleKind { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };

struct TestTiff {
  int width = 5, height = 4;
  SampleKind kind = SampleKind::Float32;
  std::vector<double> values;  // band 1, width * height, row 0 first
  int samplesPerPixel = 1;     // further bands hold values + 1000 * band
  bool tiled = false;          // 16 x 16 tiles
  uint16_t compression = COMPRESSION_NONE;
  int overviews = 0;  // extra half-size directories after the first (like a COG)
  // GeoKeys (written only when some key is set) and placement tags.
  std::optional<int> modelType, rasterType, geographicType, angularUnits, projectedType,
      linearUnits, verticalUnits;
  std::optional<double> linearUnitSizeM;
  std::vector<double> pixelScale, tiePoints, transformation;
  std::optional<std::string> gdalNodata;
};

inline std::vector<double> rampValues(int width, int height, double scale = 1.0) {
  std::vector<double> v(static_cast<size_t>(width) * static_cast<size_t>(height));
  for (size_t i = 0; i < v.size(); ++i) v[i] = scale * (static_cast<double>(i) * 7.0 - 20.0);
  return v;
}

namespace detail {

inline void sampleFormat(SampleKind kind, uint16_t& format, uint16_t& bits) {
  switch (kind) {
    case SampleKind::Int8: format = SAMPLEFORMAT_INT, bits = 8; return;
    case SampleKind::UInt8: format = SAMPLEFORMAT_UINT, bits = 8; return;
    case SampleKind::Int16: format = SAMPLEFORMAT_INT, bits = 16; return;
    case SampleKind::UInt16: format = SAMPLEFORMAT_UINT, bits = 16; return;
    case SampleKind::Int32: format = SAMPLEFORMAT_INT, bits = 32; return;
    case SampleKind::UInt32: format = SAMPLEFORMAT_UINT, bits = 32; return;
    case SampleKind::Float32: format = SAMPLEFORMAT_IEEEFP, bits = 32; return;
    case SampleKind::Float64: format = SAMPLEFORMAT_IEEEFP, bits = 64; return;
  }
}

template <typename T>
void append(std::vector<uint8_t>& bytes, double value) {
  const T v = static_cast<T>(value);
  const auto* p = reinterpret_cast<const uint8_t*>(&v);
  bytes.insert(bytes.end(), p, p + sizeof(T));
}

inline void appendSample(std::vector<uint8_t>& bytes, SampleKind kind, double value) {
  switch (kind) {
    case SampleKind::Int8: append<int8_t>(bytes, value); return;
    case SampleKind::UInt8: append<uint8_t>(bytes, value); return;
    case SampleKind::Int16: append<int16_t>(bytes, value); return;
    case SampleKind::UInt16: append<uint16_t>(bytes, value); return;
    case SampleKind::Int32: append<int32_t>(bytes, value); return;
    case SampleKind::UInt32: append<uint32_t>(bytes, value); return;
    case SampleKind::Float32: append<float>(bytes, value); return;
    case SampleKind::Float64: append<double>(bytes, value); return;
  }
}

// Pixel bytes of the region [x0, x0+w) x [y0, y0+h) (zero outside the image).
inline std::vector<uint8_t> region(const TestTiff& t, const std::vector<double>& values, int width,
                                   int height, int x0, int y0, int w, int h) {
  std::vector<uint8_t> bytes;
  for (int y = y0; y < y0 + h; ++y) {
    for (int x = x0; x < x0 + w; ++x) {
      for (int s = 0; s < t.samplesPerPixel; ++s) {
        const bool inside = x < width && y < height;
        const double v = inside ? values[static_cast<size_t>(y) * static_cast<size_t>(width) +
                                         static_cast<size_t>(x)] +
                                      1000.0 * s
                                : 0.0;
        appendSample(bytes, t.kind, v);
      }
    }
  }
  return bytes;
}

inline void writeDirectory(TIFF* tif, const TestTiff& t, const std::vector<double>& values,
                           int width, int height, bool first) {
  uint16_t format = 0, bits = 0;
  sampleFormat(t.kind, format, bits);
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(width));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(height));
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, static_cast<uint16_t>(t.samplesPerPixel));
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, bits);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, format);
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, t.compression);
  if (t.samplesPerPixel > 1) {
    std::vector<uint16_t> extra(static_cast<size_t>(t.samplesPerPixel - 1),
                                EXTRASAMPLE_UNSPECIFIED);
    TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, static_cast<uint16_t>(extra.size()), extra.data());
  }
  if (!first) TIFFSetField(tif, TIFFTAG_SUBFILETYPE, FILETYPE_REDUCEDIMAGE);
  if (first) {
    if (!t.pixelScale.empty())
      TIFFSetField(tif, TIFFTAG_GEOPIXELSCALE, static_cast<uint16_t>(t.pixelScale.size()),
                   t.pixelScale.data());
    if (!t.tiePoints.empty())
      TIFFSetField(tif, TIFFTAG_GEOTIEPOINTS, static_cast<uint16_t>(t.tiePoints.size()),
                   t.tiePoints.data());
    if (!t.transformation.empty())
      TIFFSetField(tif, TIFFTAG_GEOTRANSMATRIX, static_cast<uint16_t>(t.transformation.size()),
                   t.transformation.data());
    if (t.gdalNodata) {
      // libtiff 4.5 does not know GDAL_NODATA (42113): declare it for this file.
      static const TIFFFieldInfo nodataField = {
          42113, -1, -1, TIFF_ASCII, FIELD_CUSTOM, 1, 0, const_cast<char*>("GDALNoDataValue")};
      TIFFMergeFieldInfo(tif, &nodataField, 1);
      TIFFSetField(tif, 42113, t.gdalNodata->c_str());
    }
    const bool anyKey = t.modelType || t.rasterType || t.geographicType || t.angularUnits ||
                        t.projectedType || t.linearUnits || t.verticalUnits;
    if (anyKey) {
      GTIF* gtif = GTIFNew(tif);
      const auto key = [&](geokey_t id, const std::optional<int>& v) {
        if (v) GTIFKeySet(gtif, id, TYPE_SHORT, 1, *v);
      };
      key(GTModelTypeGeoKey, t.modelType);
      key(GTRasterTypeGeoKey, t.rasterType);
      key(GeographicTypeGeoKey, t.geographicType);
      key(GeogAngularUnitsGeoKey, t.angularUnits);
      key(ProjectedCSTypeGeoKey, t.projectedType);
      key(ProjLinearUnitsGeoKey, t.linearUnits);
      key(VerticalUnitsGeoKey, t.verticalUnits);
      if (t.linearUnitSizeM)
        GTIFKeySet(gtif, ProjLinearUnitSizeGeoKey, TYPE_DOUBLE, 1, *t.linearUnitSizeM);
      GTIFWriteKeys(gtif);
      GTIFFree(gtif);
    }
  }
  if (t.tiled) {
    constexpr int kTile = 16;
    TIFFSetField(tif, TIFFTAG_TILEWIDTH, kTile);
    TIFFSetField(tif, TIFFTAG_TILELENGTH, kTile);
    for (int y = 0; y < height; y += kTile) {
      for (int x = 0; x < width; x += kTile) {
        std::vector<uint8_t> tile = region(t, values, width, height, x, y, kTile, kTile);
        if (TIFFWriteTile(tif, tile.data(), static_cast<uint32_t>(x), static_cast<uint32_t>(y), 0,
                          0) < 0)
          throw std::runtime_error("TIFFWriteTile failed");
      }
    }
  } else {
    const int rowsPerStrip = 2;
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, rowsPerStrip);
    for (int y = 0, strip = 0; y < height; y += rowsPerStrip, ++strip) {
      const int rows = std::min(rowsPerStrip, height - y);
      std::vector<uint8_t> bytes = region(t, values, width, height, 0, y, width, rows);
      if (TIFFWriteEncodedStrip(tif, static_cast<uint32_t>(strip), bytes.data(),
                                static_cast<tmsize_t>(bytes.size())) < 0)
        throw std::runtime_error("TIFFWriteEncodedStrip failed");
    }
  }
  if (!TIFFWriteDirectory(tif)) throw std::runtime_error("TIFFWriteDirectory failed");
}

}  // namespace detail

inline void writeTestTiff(const std::filesystem::path& path, const TestTiff& t) {
  XTIFFInitialize();
  std::vector<double> values = t.values.empty() ? rampValues(t.width, t.height) : t.values;
  if (values.size() != static_cast<size_t>(t.width) * static_cast<size_t>(t.height))
    throw std::invalid_argument("TestTiff values must be width * height");
  TIFF* tif = TIFFOpen(path.c_str(), "w");
  if (!tif) throw std::runtime_error("cannot create " + path.string());
  detail::writeDirectory(tif, t, values, t.width, t.height, true);
  int w = t.width, h = t.height;
  for (int level = 0; level < t.overviews; ++level) {
    // Overviews hold other numbers, so reading one by mistake shows.
    w = std::max(1, w / 2);
    h = std::max(1, h / 2);
    std::vector<double> small(static_cast<size_t>(w) * static_cast<size_t>(h), 99.0);
    detail::writeDirectory(tif, t, small, w, h, false);
  }
  TIFFClose(tif);
}

// Overwrites a single-valued SHORT or LONG tag, as a LONG, of the first directory of a
// little-endian classic TIFF (to build files libtiff would not write).
inline void patchTiffTag(const std::filesystem::path& path, uint16_t tag, uint32_t value) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  const auto read = [&](std::streamoff at, int bytes) {
    unsigned char b[4] = {};
    file.seekg(at);
    file.read(reinterpret_cast<char*>(b), bytes);
    return uint32_t{b[0]} | uint32_t{b[1]} << 8 | uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24;
  };
  const uint32_t ifd = read(4, 4);
  const uint32_t count = read(ifd, 2);
  for (uint32_t i = 0; i < count; ++i) {
    const std::streamoff entry = ifd + 2 + 12 * static_cast<std::streamoff>(i);
    if (read(entry, 2) != tag) continue;
    // Rewritten as LONG, so that any 32-bit value fits.
    const unsigned char b[6] = {4,
                                0,
                                static_cast<unsigned char>(value),
                                static_cast<unsigned char>(value >> 8),
                                static_cast<unsigned char>(value >> 16),
                                static_cast<unsigned char>(value >> 24)};
    file.seekp(entry + 2);
    file.write(reinterpret_cast<const char*>(b), 2);
    file.seekp(entry + 8);
    file.write(reinterpret_cast<const char*>(b + 2), 4);
    return;
  }
  throw std::runtime_error("patchTiffTag: no tag " + std::to_string(tag));
}

// A little-endian int16 TIFF laid out as header, directory, then one strip of
// pixels, so that cutting the file short truncates the pixels and keeps the
// directory. The header may claim any size (for the size-limit tests).
inline void writeHandmadeInt16Tiff(const std::filesystem::path& path, uint32_t width,
                                   uint32_t height, const std::vector<int16_t>& pixels,
                                   size_t keepPixelBytes) {
  std::vector<uint8_t> b = {'I', 'I', 42, 0, 8, 0, 0, 0};
  const auto u16 = [&](uint32_t v) {
    b.push_back(static_cast<uint8_t>(v));
    b.push_back(static_cast<uint8_t>(v >> 8));
  };
  const auto u32 = [&](uint32_t v) {
    u16(v & 0xffff);
    u16(v >> 16);
  };
  const uint32_t entries = 10;
  const uint32_t dataOffset = 8 + 2 + entries * 12 + 4;
  const uint64_t pixelBytes = uint64_t{width} * height * 2;
  const auto entry = [&](uint32_t tag, uint32_t type, uint32_t value) {
    u16(tag);
    u16(type);
    u32(1);
    if (type == 3) {
      u16(value);
      u16(0);
    } else {
      u32(value);
    }
  };
  u16(entries);
  entry(256, 4, width);
  entry(257, 4, height);
  entry(258, 3, 16);
  entry(259, 3, 1);
  entry(262, 3, 1);
  entry(273, 4, dataOffset);
  entry(277, 3, 1);
  entry(278, 4, height);
  entry(279, 4, static_cast<uint32_t>(std::min<uint64_t>(pixelBytes, 0xffffffffu)));
  entry(339, 3, 2);
  u32(0);
  for (int16_t p : pixels) u16(static_cast<uint16_t>(p));
  b.resize(std::min(b.size(), dataOffset + keepPixelBytes));
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

}  // namespace aal::test
