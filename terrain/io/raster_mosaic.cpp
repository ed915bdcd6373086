#include "aperture/terrain/io/raster_mosaic.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <vector>

#include <cpl_string.h>
#include <gdal_priv.h>
#include <gdal_utils.h>

#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/io/pixel_checksum.h"

namespace aal {

namespace {

// The raster at `path`, a regular file, opened by GDAL as that file
// (gdalFileName); null otherwise.
GDALDatasetUniquePtr openRasterFile(const std::string& path) {
  if (inputStatus(path).kind != InputKind::File) return nullptr;
  ensureGdal();
  CPLErrorReset();
  return GDALDatasetUniquePtr(GDALDataset::Open(
      gdalFileName(path).c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
}

}  // namespace

std::optional<RasterShape> readRasterShape(const std::string& path) {
  GDALDatasetUniquePtr dataset = openRasterFile(path);
  if (!dataset || dataset->GetRasterCount() < 1) return std::nullopt;
  RasterShape shape;
  shape.width = dataset->GetRasterXSize();
  shape.height = dataset->GetRasterYSize();
  shape.bands = dataset->GetRasterCount();
  shape.float32 = dataset->GetRasterBand(1)->GetRasterDataType() == GDT_Float32;
  for (CSLConstList item = dataset->GetMetadata(); item != nullptr && *item != nullptr; ++item) {
    char* name = nullptr;
    const char* value = CPLParseNameValue(*item, &name);
    if (name != nullptr && value != nullptr) shape.metadata[name] = value;
    CPLFree(name);
  }
  return shape;
}

std::optional<uint64_t> floatRasterChecksum(const std::string& path) {
  GDALDatasetUniquePtr dataset = openRasterFile(path);
  if (!dataset || dataset->GetRasterCount() < 1) return std::nullopt;
  const int width = dataset->GetRasterXSize(), height = dataset->GetRasterYSize();
  GDALRasterBand& band = *dataset->GetRasterBand(1);
  PixelChecksum sum(height);
  // Bands of rows of at most 16 MB: a tile of the largest size is not held whole.
  const int bandRows = std::max(1, static_cast<int>((size_t{16} << 20) / (4 * size_t(width))));
  std::vector<float> rows;
  for (int row = 0; row < height; row += bandRows) {
    const int count = std::min(bandRows, height - row);
    rows.resize(static_cast<size_t>(count) * width);
    if (band.RasterIO(GF_Read, 0, row, width, count, rows.data(), width, count, GDT_Float32, 0, 0,
                      nullptr) != CE_None) {
      return std::nullopt;
    }
    for (int i = 0; i < count; ++i) {
      sum.addRow(row + i, rows.data() + static_cast<size_t>(i) * width, sizeof(float) * width);
    }
  }
  return sum.value();
}

namespace {

// The tile's band descriptions and units onto the mosaic (GDALBuildVRT
// leaves them out), so that GIS tools name its bands as the tiles'.
void copyBandLabels(const std::string& tile, GDALDataset& mosaic) {
  GDALDatasetUniquePtr first(GDALDataset::Open(tile.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!first) return;
  const int bands = std::min(first->GetRasterCount(), mosaic.GetRasterCount());
  for (int b = 1; b <= bands; ++b) {
    GDALRasterBand* from = first->GetRasterBand(b);
    mosaic.GetRasterBand(b)->SetDescription(from->GetDescription());
    mosaic.GetRasterBand(b)->SetUnitType(from->GetUnitType());
  }
}

}  // namespace

void writeVrtMosaic(const std::string& path, const std::vector<std::string>& tiles) {
  namespace fs = std::filesystem;
  ensureGdal();
  AtomicOutput output(path);
  // Absolute names on both sides: the VRT driver then writes the tiles
  // under its folder relative to it, whatever the working directory.
  const std::string temporary = fs::absolute(output.temporaryPath()).string();
  CPLStringList names;
  for (const std::string& tile : tiles) names.AddString(fs::absolute(tile).string().c_str());
  // The finest resolution, not the mean: the tiles share one, which the
  // mean of many would change in its last bits.
  CPLStringList arguments;
  arguments.AddString("-resolution");
  arguments.AddString("highest");
  arguments.AddString("-q");
  GDALBuildVRTOptions* options = GDALBuildVRTOptionsNew(arguments.List(), nullptr);
  if (options == nullptr) throw output.failure(gdalLastError(), "the VRT");
  CPLErrorReset();
  int usageError = FALSE;
  GDALDatasetH vrt =
      GDALBuildVRT(temporary.c_str(), names.Count(), nullptr, names.List(), options, &usageError);
  GDALBuildVRTOptionsFree(options);
  if (vrt == nullptr) throw output.failure(gdalLastError(), "the VRT");
  if (!tiles.empty()) copyBandLabels(tiles.front(), *GDALDataset::FromHandle(vrt));
  // Closing the dataset writes it.
  GDALClose(vrt);
  if (CPLGetLastErrorType() == CE_Failure) {
    throw output.failure(gdalLastError(), "the VRT");
  }
  output.commit();
}

}  // namespace aal
