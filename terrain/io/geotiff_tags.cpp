#include "geotiff_tags.h"

#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <type_traits>

#include <geotiff/geotiff.h>
#include <geotiff/xtiffio.h>
#include <tiffio.h>

#include "errors.h"
#include "tiff_handles.h"

namespace aal {

namespace {

void onGeoTiffMessage(GTIF* gtif, int level, const char* fmt, ...) {
  if (level != LIBGEOTIFF_ERROR) return;
  auto* messages = static_cast<TiffMessages*>(GTIFGetUserData(gtif));
  va_list args;
  va_start(args, fmt);
  messages->add(nullptr, fmt, args);
  va_end(args);
}

// Values of an array tag. libtiff registers GeoTIFF tags (through
// XTIFFInitialize) with a 16-bit count but reads tags it does not know, like
// GDAL_NODATA in libtiff 4.5, as anonymous fields with a 32-bit count: ask the
// field which one applies.
template <typename T>
std::vector<T> arrayTag(TIFF* tif, uint32_t tag) {
  const TIFFField* field = TIFFFindField(tif, tag, TIFF_ANY);  // quiet when unknown
  if (!field) return {};
  T* values = nullptr;
  uint32_t count = 0;
  if (!TIFFFieldPassCount(field)) {
    if (TIFFGetField(tif, tag, &values) != 1 || !values) return {};
    if constexpr (std::is_same_v<T, char>) {
      count = static_cast<uint32_t>(std::strlen(values));
    } else {
      return {};  // fixed-count arrays are not used by any tag read here
    }
  } else if (TIFFFieldReadCount(field) == TIFF_VARIABLE2) {
    if (TIFFGetField(tif, tag, &count, &values) != 1 || !values) return {};
  } else {
    uint16_t shortCount = 0;
    if (TIFFGetField(tif, tag, &shortCount, &values) != 1 || !values) return {};
    count = shortCount;
  }
  return std::vector<T>(values, values + count);
}

std::optional<int> shortKey(GTIF* gtif, geokey_t key) {
  unsigned short value = 0;
  if (GTIFKeyGetSHORT(gtif, key, &value, 0, 1) != 1) return std::nullopt;
  return value;
}

std::optional<double> doubleKey(GTIF* gtif, geokey_t key) {
  double value = 0;
  if (GTIFKeyGetDOUBLE(gtif, key, &value, 0, 1) != 1) return std::nullopt;
  return value;
}

void readGeoKeys(const std::string& path, TIFF* tif, GeoTiffTags& tags) {
  TiffMessages messages;  // of libgeotiff only
  tags.hasGeoKeys = !arrayTag<uint16_t>(tif, TIFFTAG_GEOKEYDIRECTORY).empty();
  if (!tags.hasGeoKeys) return;
  GtifHandle gtif(GTIFNewEx(tif, onGeoTiffMessage, &messages));
  if (!gtif || !messages.errors.empty()) {
    throw InputError(path + ": corrupt GeoKey directory: " +
                     (messages.errors.empty() ? "libgeotiff cannot parse it" : messages.errors));
  }
  tags.modelType = shortKey(gtif.get(), GTModelTypeGeoKey);
  tags.rasterType = shortKey(gtif.get(), GTRasterTypeGeoKey);
  tags.geographicType = shortKey(gtif.get(), GeographicTypeGeoKey);
  tags.angularUnits = shortKey(gtif.get(), GeogAngularUnitsGeoKey);
  tags.angularUnitSizeRad = doubleKey(gtif.get(), GeogAngularUnitSizeGeoKey);
  tags.projectedType = shortKey(gtif.get(), ProjectedCSTypeGeoKey);
  tags.linearUnits = shortKey(gtif.get(), ProjLinearUnitsGeoKey);
  tags.linearUnitSizeM = doubleKey(gtif.get(), ProjLinearUnitSizeGeoKey);
  tags.verticalUnits = shortKey(gtif.get(), VerticalUnitsGeoKey);
}

}  // namespace

GeoTiffTags readGeoTiffTags(const std::string& path) {
  TiffMessages messages;
  TiffHandle tif = openTiff(path, "r", messages);
  if (!tif) {
    throw InputError(path + ": not a readable TIFF: " +
                     (messages.errors.empty() ? "libtiff cannot open it" : messages.errors));
  }

  GeoTiffTags tags;
  uint32_t width = 0, height = 0;
  uint16_t samples = 1, bits = 1;
  TIFFGetField(tif.get(), TIFFTAG_IMAGEWIDTH, &width);
  TIFFGetField(tif.get(), TIFFTAG_IMAGELENGTH, &height);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_SAMPLESPERPIXEL, &samples);
  TIFFGetFieldDefaulted(tif.get(), TIFFTAG_BITSPERSAMPLE, &bits);
  tags.width = width;
  tags.height = height;
  tags.samplesPerPixel = samples;
  tags.bitsPerSample = bits;
  if (TIFFIsTiled(tif.get())) {
    TIFFGetField(tif.get(), TIFFTAG_TILEWIDTH, &tags.tileWidth);
    TIFFGetField(tif.get(), TIFFTAG_TILELENGTH, &tags.tileLength);
  } else {
    TIFFGetFieldDefaulted(tif.get(), TIFFTAG_ROWSPERSTRIP, &tags.rowsPerStrip);
  }

  tags.pixelScale = arrayTag<double>(tif.get(), TIFFTAG_GEOPIXELSCALE);
  tags.tiePoints = arrayTag<double>(tif.get(), TIFFTAG_GEOTIEPOINTS);
  tags.transformation = arrayTag<double>(tif.get(), TIFFTAG_GEOTRANSMATRIX);
  const std::vector<char> nodata = arrayTag<char>(tif.get(), TIFFTAG_GDAL_NODATA);
  if (!nodata.empty()) {
    // An ASCII value: stop at its terminating NUL.
    tags.gdalNodata = std::string(nodata.data(), strnlen(nodata.data(), nodata.size()));
  }
  readGeoKeys(path, tif.get(), tags);
  return tags;
}

}  // namespace aal
