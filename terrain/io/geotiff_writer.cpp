#include "geotiff_writer.h"

#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <geotiff/geotiff.h>
#include <geotiff/geovalues.h>
#include <geotiff/xtiffio.h>
#include <tiffio.h>

#include "atomic_file.h"
#include "dem_options.h"
#include "tiff_handles.h"

namespace aal {

namespace {

constexpr int kUserDefined = 32767;
constexpr int kRowsPerStrip = 16;

int linearUnitCode(double linearUnitM) {
  if (linearUnitM == 1.0) return 9001;
  if (linearUnitM == 0.3048) return 9002;
  if (linearUnitM == 1200.0 / 3937.0) return 9003;
  return kUserDefined;
}

bool writeGeoKeys(TIFF* tif, const GeoReference& geo) {
  // Tie point on the north-west corner of texel (0, 0) (PixelIsArea).
  const double scale[3] = {geo.stepX, geo.stepY, 0.0};
  const double tiePoint[6] = {
      0.0, 0.0, 0.0, geo.originX - 0.5 * geo.stepX, geo.originY + 0.5 * geo.stepY, 0.0};
  if (!TIFFSetField(tif, TIFFTAG_GEOPIXELSCALE, 3, scale) ||
      !TIFFSetField(tif, TIFFTAG_GEOTIEPOINTS, 6, tiePoint)) {
    return false;
  }
  GtifHandle gtif(GTIFNew(tif));
  if (!gtif) return false;
  GTIFKeySet(gtif.get(), GTRasterTypeGeoKey, TYPE_SHORT, 1, RasterPixelIsArea);
  if (geo.crs == CrsKind::Geographic) {
    GTIFKeySet(gtif.get(), GTModelTypeGeoKey, TYPE_SHORT, 1, ModelTypeGeographic);
    GTIFKeySet(gtif.get(), GeographicTypeGeoKey, TYPE_SHORT, 1, geo.epsg > 0 ? geo.epsg : 4326);
    GTIFKeySet(gtif.get(), GeogAngularUnitsGeoKey, TYPE_SHORT, 1, Angular_Degree);
  } else {
    GTIFKeySet(gtif.get(), GTModelTypeGeoKey, TYPE_SHORT, 1, ModelTypeProjected);
    GTIFKeySet(gtif.get(), ProjectedCSTypeGeoKey, TYPE_SHORT, 1,
               geo.epsg > 0 && geo.epsg < kUserDefined ? geo.epsg : kUserDefined);
    const int unit = linearUnitCode(geo.linearUnitM);
    GTIFKeySet(gtif.get(), ProjLinearUnitsGeoKey, TYPE_SHORT, 1, unit);
    if (unit == kUserDefined) {
      GTIFKeySet(gtif.get(), ProjLinearUnitSizeGeoKey, TYPE_DOUBLE, 1, geo.linearUnitM);
    }
  }
  return GTIFWriteKeys(gtif.get()) != 0;
}

void writeTiff(const std::string& path, int width, int height, const float* data,
               const GeoReference& geo) {
  TiffMessages messages;
  // BigTIFF when the pixels alone come near the 4 GiB offset limit.
  const double bytes = 4.0 * width * height;
  const char* mode = bytes > 3.5e9 ? "w8" : "w";
  TiffHandle tif = openTiff(path, mode, messages);
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error("cannot write " + path + ": " + what +
                             (messages.errors.empty() ? "" : ": " + messages.errors));
  };
  if (!tif) fail("cannot create the file");
  TIFF* t = tif.get();
  TIFFSetField(t, TIFFTAG_IMAGEWIDTH, static_cast<uint32_t>(width));
  TIFFSetField(t, TIFFTAG_IMAGELENGTH, static_cast<uint32_t>(height));
  TIFFSetField(t, TIFFTAG_SAMPLESPERPIXEL, 1);
  TIFFSetField(t, TIFFTAG_BITSPERSAMPLE, 32);
  TIFFSetField(t, TIFFTAG_SAMPLEFORMAT, SAMPLEFORMAT_IEEEFP);
  TIFFSetField(t, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
  TIFFSetField(t, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
  TIFFSetField(t, TIFFTAG_COMPRESSION, COMPRESSION_ADOBE_DEFLATE);
  TIFFSetField(t, TIFFTAG_PREDICTOR, PREDICTOR_FLOATINGPOINT);
  TIFFSetField(t, TIFFTAG_ROWSPERSTRIP, static_cast<uint32_t>(kRowsPerStrip));
  if (geo.crs != CrsKind::None && !writeGeoKeys(t, geo)) fail("cannot write the GeoTIFF tags");

  // libtiff's predictor works in place: hand it a copy of each strip.
  std::vector<float> strip(static_cast<size_t>(width) * kRowsPerStrip);
  for (int row = 0, index = 0; row < height; row += kRowsPerStrip, ++index) {
    const int rows = std::min(kRowsPerStrip, height - row);
    const size_t count = static_cast<size_t>(width) * static_cast<size_t>(rows);
    std::copy(data + static_cast<size_t>(row) * static_cast<size_t>(width),
              data + static_cast<size_t>(row) * static_cast<size_t>(width) + count, strip.begin());
    if (TIFFWriteEncodedStrip(t, static_cast<uint32_t>(index), strip.data(),
                              static_cast<tmsize_t>(count * sizeof(float))) < 0) {
      fail("cannot write rows " + std::to_string(row));
    }
  }
  if (!TIFFWriteDirectory(t)) fail("cannot finish the file");
  TIFF* raw = tif.release();
  TIFFClose(raw);
  if (!messages.errors.empty()) fail("libtiff reported an error");
}

}  // namespace

void writeFloatGeoTiff(const std::string& path, int width, int height, const float* data,
                       const GeoReference& geo) {
  if (width < 1 || height < 1 || width > kMaxDemSide || height > kMaxDemSide || !data) {
    throw std::invalid_argument("writeFloatGeoTiff: size must be in [1, " +
                                std::to_string(kMaxDemSide) + "] and data non-null");
  }
  if (geo.crs != CrsKind::None &&
      !(geo.stepX > 0.0 && geo.stepY > 0.0 && std::isfinite(geo.stepX) &&
        std::isfinite(geo.stepY) && std::isfinite(geo.originX) && std::isfinite(geo.originY) &&
        geo.linearUnitM > 0.0)) {
    throw std::invalid_argument("writeFloatGeoTiff: georeference needs finite positive steps");
  }
  AtomicOutput output(path);
  writeTiff(output.temporaryPath().string(), width, height, data, geo);
  output.commit();
}

}  // namespace aal
