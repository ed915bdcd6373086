// libFuzzer target: rasters GDAL can describe, built from the input's bytes
// in GDAL's MEM driver — size, sample type, bands and their colour
// interpretation, nodata, scale and offset, unit, geotransform, one of a
// few CRSs, a mask, samples — then read whole and as a window through
// DemSource and loadDem's later steps. Checks that windows equal the whole
// and that heights stay finite.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include <fuzzer/FuzzedDataProvider.h>
#include <ogr_spatialref.h>

#include "aperture/fuzz/fuzz_common.h"
#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"

namespace {

const char* const kCrs[] = {"",          "EPSG:4326", "EPSG:32616", "EPSG:3857",
                            "EPSG:4807", "EPSG:2229", "EPSG:4978",  "EPSG:3035"};
const GDALDataType kTypes[] = {GDT_Byte,    GDT_UInt16,  GDT_Int16, GDT_UInt32, GDT_Int32,
                               GDT_Float32, GDT_Float64, GDT_Int64, GDT_UInt64, GDT_CInt16};
const GDALColorInterp kColours[] = {GCI_GrayIndex, GCI_Undefined, GCI_AlphaBand, GCI_RedBand,
                                    GCI_PaletteIndex};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  aal::fuzz::initGdal();
  FuzzedDataProvider in(data, size);
  const int width = in.ConsumeIntegralInRange(1, 40), height = in.ConsumeIntegralInRange(1, 40);
  const int bands = in.ConsumeIntegralInRange(1, 3);
  const GDALDataType type = in.PickValueInArray(kTypes);
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDatasetUniquePtr ds(mem->Create("", width, height, bands, type, nullptr));
  if (!ds) return 0;
  for (int b = 1; b <= bands; ++b) {
    GDALRasterBand* band = ds->GetRasterBand(b);
    band->SetColorInterpretation(in.PickValueInArray(kColours));
    std::vector<double> values(static_cast<size_t>(width) * height);
    for (double& v : values) v = in.ConsumeFloatingPoint<double>();
    if (band->RasterIO(GF_Write, 0, 0, width, height, values.data(), width, height, GDT_Float64, 0,
                       0, nullptr) != CE_None) {
      return 0;
    }
  }
  GDALRasterBand* first = ds->GetRasterBand(1);
  if (in.ConsumeBool()) first->SetNoDataValue(in.ConsumeFloatingPoint<double>());
  if (in.ConsumeBool()) first->SetScale(in.ConsumeFloatingPoint<double>());
  if (in.ConsumeBool()) first->SetOffset(in.ConsumeFloatingPoint<double>());
  if (in.ConsumeBool()) first->SetUnitType(in.ConsumeBool() ? "ft" : "furlong");
  if (in.ConsumeBool()) {
    double t[6];
    for (double& v : t) v = in.ConsumeFloatingPoint<double>();
    if (in.ConsumeBool()) t[2] = t[4] = 0.0;
    ds->SetGeoTransform(t);
    const char* crs = in.PickValueInArray(kCrs);
    OGRSpatialReference srs;
    if (*crs != '\0' && srs.SetFromUserInput(crs) == OGRERR_NONE) ds->SetSpatialRef(&srs);
  }
  if (in.ConsumeBool() && ds->CreateMaskBand(GMF_PER_DATASET) == CE_None) {
    std::vector<GByte> mask(static_cast<size_t>(width) * height);
    for (GByte& m : mask) m = in.ConsumeBool() ? 255 : 0;
    if (first->GetMaskBand()->RasterIO(GF_Write, 0, 0, width, height, mask.data(), width, height,
                                       GDT_Byte, 0, 0, nullptr) != CE_None) {
      return 0;
    }
  }
  // MEM datasets are not reachable by name: go through a GeoTIFF in memory.
  const std::string path = "/vsimem/fuzz_raster.tif";
  GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
  GDALDatasetUniquePtr copy(
      gtiff->CreateCopy(path.c_str(), ds.get(), FALSE, nullptr, nullptr, nullptr));
  if (!copy) return 0;
  copy.reset();
  try {
    const aal::DemSource source(path, aal::fuzz::options());
    const aal::RawDem whole = source.readAll();
    const int column = in.ConsumeIntegralInRange(0, width - 1);
    const int row = in.ConsumeIntegralInRange(0, height - 1);
    const int w = in.ConsumeIntegralInRange(1, width - column);
    const int h = in.ConsumeIntegralInRange(1, height - row);
    const aal::RawDem window = source.read(column, row, w, h);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const size_t a = static_cast<size_t>(y) * w + x;
        const size_t b = static_cast<size_t>(y + row) * width + x + column;
        if (std::memcmp(&window.z[a], &whole.z[b], sizeof(float)) != 0 ||
            window.voidMask[a] != whole.voidMask[b]) {
          std::abort();
        }
      }
    }
    const aal::Heightfield f = aal::heightfieldFromRaw(whole, path, aal::fuzz::options());
    for (const float z : f.z) {
      if (!std::isfinite(z)) std::abort();
    }
  } catch (const aal::InputError&) {
  }
  VSIUnlink(path.c_str());
  return 0;
}
