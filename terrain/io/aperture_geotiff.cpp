#include "aperture/terrain/io/aperture_geotiff.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include <gdal_priv.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/band_labels.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/io/pixel_checksum.h"
#include "aperture/terrain/version.h"

namespace aal {

namespace {

using Items = std::vector<std::pair<std::string, std::string>>;

// "%.17g": a double in words that reads back as itself.
std::string exact(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

// The EXR's aal: attributes as GDAL metadata items (default domain, so
// that gdalinfo lists them; names without ':', which GDAL's NAME=VALUE
// lists read as a separator).
Items apertureItems(const ApertureMap& map) {
  const ApertureMapInfo& i = map.info;
  Items items = {
      {"AAL_VERSION", std::to_string(i.version)},
      {"AAL_AZIMUTHS", std::to_string(i.azimuths)},
      {"AAL_METHOD", i.method},
      {"AAL_CELL_SIZE_X", exact(i.cellSizeX)},
      {"AAL_CELL_SIZE_Y", exact(i.cellSizeY)},
      {"AAL_Z_SCALE", exact(i.zScale)},
      {"AAL_SOURCE", i.source},
      {"AAL_SOURCE_SIZE", std::to_string(i.sourceWidth) + "x" + std::to_string(i.sourceHeight)},
      {"AAL_SOURCE_CHECKSUM", i.sourceChecksum},
      {"AAL_EDGE", i.edge},
      {"AAL_CURVATURE", i.curvature ? "1" : "0"},
      {"AAL_REFRACTION", exact(i.refraction)},
      {"AAL_MAX_DISTANCE", exact(i.maxDistanceM)},
      {"AAL_SOFTWARE", softwareName()},
  };
  if (i.originCol != 0 || i.originRow != 0 || map.width != i.sourceWidth ||
      map.height != i.sourceHeight) {
    items.emplace_back("AAL_TILE_ORIGIN",
                       std::to_string(i.originCol) + "," + std::to_string(i.originRow));
  }
  return items;
}

// The checksum of the map's rows of 4 floats per texel, as stored.
uint64_t floatRowsChecksum(const ApertureMap& map) {
  const size_t rowFloats = static_cast<size_t>(map.width) * 4;
  PixelChecksum sum(map.height);
  for (int y = 0; y < map.height; ++y) {
    sum.addRow(y, map.texels.data() + static_cast<size_t>(y) * rowFloats,
               rowFloats * sizeof(float));
  }
  return sum.value();
}

}  // namespace

bool isGeoTiffPath(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".tif" || extension == ".tiff";
}

void writeApertureGeoTiff(const std::string& path, const ApertureMap& map, const GeoReference& geo,
                          RasterWriteOptions options) {
  if (map.texels.size() != map.texelCount() * 4) {
    throw std::invalid_argument("writeApertureGeoTiff: the map has " +
                                std::to_string(map.texels.size()) + " floats, not 4 per texel");
  }
  const auto labels = apertureMapBandLabels();
  options.bandLabels.assign(labels.begin(), labels.end());
  options.nodata.reset();  // every texel has a cap: the bake fills the DEM's voids
  options.metadata = apertureItems(map);
  options.metadata.emplace_back("AAL_PIXEL_CHECKSUM", checksumHex(floatRowsChecksum(map)));
  writeGeoTiff(path,
               RasterImage{map.width, map.height, 4, RasterSampleType::Float32, map.texels.data()},
               geo, options);
}

struct ApertureGeoTiff::Impl {
  GDALDatasetUniquePtr dataset;
  std::string path;
  int width = 0, height = 0;
  std::optional<uint64_t> expected;  // AAL_PIXEL_CHECKSUM
  std::optional<PixelChecksum> sum;
};

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& what) {
  throw InputError("aperture map " + path + " " + what);
}

// The item `name`, or InputError naming it when it is missing.
std::string item(GDALDataset& dataset, const std::string& path, const char* name) {
  const char* value = dataset.GetMetadataItem(name);
  if (value == nullptr) refuse(path, std::string("lacks the metadata item ") + name);
  return value;
}

double number(GDALDataset& dataset, const std::string& path, const char* name) {
  const std::string text = item(dataset, path, name);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || !std::isfinite(value)) {
    refuse(path, std::string("has a malformed ") + name + " item: '" + text + "'");
  }
  return value;
}

// The header's fields from the AAL_* items.
ApertureMapInfo readInfo(GDALDataset& d, const std::string& path) {
  ApertureMapInfo i;
  i.version = static_cast<int>(number(d, path, "AAL_VERSION"));
  i.azimuths = static_cast<int>(number(d, path, "AAL_AZIMUTHS"));
  i.method = item(d, path, "AAL_METHOD");
  i.cellSizeX = number(d, path, "AAL_CELL_SIZE_X");
  i.cellSizeY = number(d, path, "AAL_CELL_SIZE_Y");
  i.zScale = number(d, path, "AAL_Z_SCALE");
  i.source = item(d, path, "AAL_SOURCE");
  i.sourceChecksum = item(d, path, "AAL_SOURCE_CHECKSUM");
  i.edge = item(d, path, "AAL_EDGE");
  i.curvature = number(d, path, "AAL_CURVATURE") != 0;
  i.refraction = number(d, path, "AAL_REFRACTION");
  i.maxDistanceM = number(d, path, "AAL_MAX_DISTANCE");
  i.software = item(d, path, "AAL_SOFTWARE");
  if (std::sscanf(item(d, path, "AAL_SOURCE_SIZE").c_str(), "%dx%d", &i.sourceWidth,
                  &i.sourceHeight) != 2) {
    refuse(path, "has a malformed AAL_SOURCE_SIZE item");
  }
  if (const char* origin = d.GetMetadataItem("AAL_TILE_ORIGIN")) {
    if (std::sscanf(origin, "%d,%d", &i.originCol, &i.originRow) != 2) {
      refuse(path, "has a malformed AAL_TILE_ORIGIN item");
    }
  }
  return i;
}

GDALDatasetUniquePtr openDataset(const std::string& path) {
  // Looked at before GDAL opens it: a FIFO would block the open forever.
  if (requireFileOrFolder(path, "aperture map " + path) == InputKind::Missing) {
    refuse(path, "does not exist");
  }
  ensureGdal();
  CPLErrorReset();
  static const char* const kDrivers[] = {"GTiff", nullptr};
  GDALDatasetUniquePtr dataset(
      GDALDataset::Open(gdalFileName(path).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, kDrivers));
  if (!dataset) {
    throw InputError("cannot read aperture map " + path + " (truncated or corrupt?): " +
                     gdalLastError("GDAL's GeoTIFF driver does not open it"));
  }
  return dataset;
}

}  // namespace

ApertureGeoTiff::ApertureGeoTiff(const std::string& path, ApertureMapHeader& header)
    : impl_(std::make_unique<Impl>()) {
  impl_->path = path;
  impl_->dataset = openDataset(path);
  GDALDataset& d = *impl_->dataset;
  if (d.GetRasterCount() != 4 || d.GetRasterBand(1)->GetRasterDataType() != GDT_Float32) {
    refuse(path, "has " + std::to_string(d.GetRasterCount()) +
                     " bands; an aperture map has 4 float32 bands (bent normal x, y, z; arc "
                     "length)");
  }
  if (d.GetMetadataItem("AAL_VERSION") == nullptr) {
    refuse(path, "has no AAL_* metadata items: not made by aal-bake");
  }
  header.width = impl_->width = d.GetRasterXSize();
  header.height = impl_->height = d.GetRasterYSize();
  header.info = readInfo(d, path);
  header.pixelChecksum = parseChecksumHex(item(d, path, "AAL_PIXEL_CHECKSUM"));
  if (!header.pixelChecksum) refuse(path, "has a malformed AAL_PIXEL_CHECKSUM item");
  impl_->expected = header.pixelChecksum;
  impl_->sum.emplace(header.height);
}

ApertureGeoTiff::~ApertureGeoTiff() = default;
ApertureGeoTiff::ApertureGeoTiff(ApertureGeoTiff&&) noexcept = default;
ApertureGeoTiff& ApertureGeoTiff::operator=(ApertureGeoTiff&&) noexcept = default;

void ApertureGeoTiff::readFloatRows(int firstRow, int endRow, float* destination, size_t rowBytes) {
  Impl& m = *impl_;
  const int rows = endRow - firstRow;
  if (rows <= 0) return;
  const GSpacing texelBytes = 4 * sizeof(float);
  CPLErrorReset();
  if (m.dataset->RasterIO(GF_Read, 0, firstRow, m.width, rows, destination, m.width, rows,
                          GDT_Float32, 4, nullptr, texelBytes, static_cast<GSpacing>(rowBytes),
                          sizeof(float), nullptr) != CE_None) {
    throw InputError("cannot read aperture map " + m.path +
                     " (truncated or corrupt?): " + gdalLastError());
  }
  const size_t bytes = static_cast<size_t>(m.width) * texelBytes;
  for (int y = firstRow; y < endRow; ++y) {
    m.sum->addRow(y, reinterpret_cast<const char*>(destination) + (y - firstRow) * rowBytes, bytes);
  }
  if (m.sum->complete() && m.sum->value() != *m.expected) {
    throw InputError("aperture map " + m.path +
                     " is corrupt: its pixels do not match its AAL_PIXEL_CHECKSUM (" +
                     checksumHex(*m.expected) + ", pixels " + checksumHex(m.sum->value()) +
                     "); bake it again with aal-bake");
  }
}

}  // namespace aal
