#include "aperture/terrain/io/dem_source.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <vector>

#include <cpl_conv.h>
#include <cpl_vsi.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <tbb/parallel_for.h>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/declared_size_check.h"
#include "aperture/terrain/io/gdal_session.h"
#include "aperture/terrain/io/georeference.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/number_text.h"
#include "aperture/terrain/units.h"

namespace aal {

namespace {

[[noreturn]] void refuse(const std::string& path, const std::string& why) {
  throw InputError(path + ": " + why);
}

std::string oneBandHint(const std::string& path) {
  return "a DEM is one band of heights; if one of its bands holds them, take it with "
         "`gdal_translate -b N " +
         path + " dem.tif`";
}

std::string lowerCase(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return text;
}

// Metres per vertical unit for the names files use (GDAL's band unit type,
// a vertical CRS's unit); nothing for names it does not know.
std::optional<double> metresPerUnit(const std::string& name) {
  const std::string unit = lowerCase(name);
  if (unit == "m" || unit == "metre" || unit == "meter" || unit == "metres" || unit == "meters") {
    return 1.0;
  }
  if (unit == "ft" || unit == "foot" || unit == "feet" || unit == "international foot" ||
      unit == "foot (international)") {
    return 0.3048;
  }
  if (unit == "us survey foot" || unit == "us-ft" || unit == "ftus" || unit == "us_survey_foot" ||
      unit == "foot_us" || unit == "us survey feet") {
    return 1200.0 / 3937.0;
  }
  if (unit == "km" || unit == "kilometre" || unit == "kilometer") return 1000.0;
  if (unit == "cm" || unit == "centimetre" || unit == "centimeter") return 0.01;
  if (unit == "mm" || unit == "millimetre" || unit == "millimeter") return 0.001;
  return std::nullopt;
}

std::string sampleTypeName(GDALDataType type, bool signedBytes) {
  if (type == GDT_Byte) return signedBytes ? "int8" : "uint8";
  return lowerCase(GDALGetDataTypeName(type));
}

// Samples float32 holds exactly, which GDAL can convert straight into the
// heights without a float64 buffer.
bool exactInFloat(GDALDataType type) {
  return type == GDT_Byte || type == GDT_UInt16 || type == GDT_Int16 || type == GDT_Float32;
}

std::string subdatasetList(GDALDataset& dataset) {
  CSLConstList items = dataset.GetMetadata("SUBDATASETS");
  std::vector<std::string> names;
  for (CSLConstList item = items; item != nullptr && *item != nullptr; ++item) {
    const std::string entry = *item;
    const size_t equals = entry.find('=');
    if (equals != std::string::npos && entry.find("_NAME=") != std::string::npos) {
      names.push_back(entry.substr(equals + 1));
    }
  }
  if (names.empty()) return {};
  std::string text = std::to_string(names.size()) + " subdatasets; open one of them instead:";
  for (size_t i = 0; i < std::min<size_t>(names.size(), 5); ++i) text += "\n  '" + names[i] + "'";
  if (names.size() > 5) text += "\n  ...";
  return text;
}

// `gdalName`: gdalFileName(path), what GDAL is given.
GDALDatasetUniquePtr openDataset(const std::string& path, const std::string& gdalName) {
  namespace fs = std::filesystem;
  CPLErrorReset();
  if (GDALDatasetUniquePtr geoTiff = openGeoTiff(gdalName)) return geoTiff;
  ensureGdal();
  CPLErrorReset();
  GDALDatasetUniquePtr dataset(
      GDALDataset::Open(gdalName.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (dataset) return dataset;
  const std::string details = gdalLastError("unrecognised format");
  if (gdalName.starts_with("/vsi")) {
    // GDAL's /vsicurl/ says nothing when the server cannot be reached or
    // has no such file: stat it to tell that from a file that is no raster.
    VSIStatBufL stat{};
    CPLErrorReset();
    if (VSIStatExL(gdalName.c_str(), &stat, VSI_STAT_EXISTS_FLAG) != 0) {
      const bool remote = gdalName.starts_with("/vsicurl/");
      const std::string reason = gdalLastError("");
      refuse(path, remote ? "cannot be fetched: the server cannot be reached or has no such file" +
                                (reason.empty() ? std::string() : " (" + reason + ")") +
                                "; check the URL and the network (GDAL_HTTP_* and proxy settings)"
                          : "not found: the archive or the file in it does not exist" +
                                (reason.empty() ? std::string() : " (" + reason + ")"));
    }
  }
  const InputKind kind = inputStatus(path).kind;
  if (kind == InputKind::Folder) refuse(path, "is a folder, not a DEM file");
  if (kind == InputKind::File) {
    std::error_code error;
    std::ifstream probe(path, std::ios::binary);
    if (!probe) refuse(path, std::string("cannot be read: ") + std::strerror(errno));
    if (fs::file_size(path, error) == 0) refuse(path, "is empty");
  }
  refuse(path, "not a raster GDAL can read (" + details + ")");
}

}  // namespace

std::string demFormatsHelp() {
  return "DEMs are read with GDAL: GeoTIFF and COG (sparse ones too), VRT mosaics, SRTM .hgt,\n"
         "Arc/Info ASCII grids (.asc with .prj), DTED, ERDAS IMG, NetCDF, PNG and every other\n"
         "raster GDAL opens (`gdalinfo --formats`). Band 1 holds the heights; nodata, masks and\n"
         "alpha bands are voids; scale, offset and vertical units (feet) are applied; any CRS.\n"
         "Palette, RGB and complex images are refused: take one band with gdal_translate -b N.";
}

namespace {

void describeCrs(const std::string& path, const OGRSpatialReference& srs,
                 const DemLoadOptions& options, RawDem& dem) {
  GeoReference& geo = dem.geo;
  if (srs.IsGeocentric())
    refuse(path, "has a geocentric CRS; a DEM needs a geographic or projected one");
  const char* key = nullptr;
  if (srs.IsGeographic()) {
    geo.crs = CrsKind::Geographic;
    geo.angularUnitDeg = degrees(srs.GetAngularUnits(nullptr));
    geo.primeMeridianDeg = srs.GetPrimeMeridian(nullptr);
    key = "GEOGCS";
  } else if (srs.IsProjected() || srs.IsLocal()) {
    geo.crs = CrsKind::Projected;
    geo.linearUnitM = srs.GetLinearUnits(nullptr);
    key = srs.IsProjected() ? "PROJCS" : nullptr;
  } else {
    if (options.warn) {
      options.warn(path +
                   " has a CRS that is neither geographic nor projected; its placement is "
                   "ignored");
    }
    return;
  }
  const char* authority = srs.GetAuthorityName(key);
  const char* code = srs.GetAuthorityCode(key);
  if (authority == nullptr || code == nullptr) {
    OGRSpatialReference identified(srs);
    if (identified.AutoIdentifyEPSG() == OGRERR_NONE) {
      authority = identified.GetAuthorityName(key);
      code = identified.GetAuthorityCode(key);
      if (authority != nullptr && code != nullptr && std::strcmp(authority, "EPSG") == 0) {
        geo.epsg = std::atoi(code);
      }
    }
  } else if (std::strcmp(authority, "EPSG") == 0) {
    geo.epsg = std::atoi(code);
  }
  geo.srs = std::shared_ptr<const OGRSpatialReference>(
      srs.Clone(), [](OGRSpatialReference* copy) { copy->Release(); });
  if (srs.GetName() != nullptr) geo.crsName = srs.GetName();
  if (srs.IsCompound() || srs.IsVertical()) {
    const char* unitName = nullptr;
    const double unit = srs.GetTargetLinearUnits("VERT_CS", &unitName);
    if (unit > 0.0 && std::isfinite(unit)) {
      dem.zUnitM = unit;
      dem.zUnitFromFile = true;
      dem.zUnitName = unitName != nullptr ? unitName : "";
    }
  }
}

// The grid's placement in its CRS's coordinates; false when it has none.
bool describeTransform(const std::string& path, GDALDataset& dataset, RawDem& dem, bool& southUp) {
  double gt[6];
  if (dataset.GetGeoTransform(gt) != CE_None) {
    // A GeoTIFF whose pixel scale is zero or missing keeps only its tie
    // point, which GDAL hands over as a single ground control point: one
    // point cannot place a grid, so this is a missing pixel size.
    if (dataset.GetGCPCount() == 1) {
      refuse(path,
             "has a tie point but no pixel size (zero or missing in the file); give it one: "
             "`gdal_edit.py -a_ullr ULX ULY LRX LRY " +
                 path + "`");
    }
    if (dataset.GetGCPCount() > 0) {
      refuse(path,
             "is placed by ground control points only; warp it onto a grid first: "
             "`gdalwarp " +
                 path + " dem.tif`");
    }
    return false;
  }
  if (gt[1] == 0.0 || gt[5] == 0.0 || !std::isfinite(gt[1]) || !std::isfinite(gt[5])) {
    refuse(path, "has a pixel size of " + numberText(gt[1]) + " x " + numberText(-gt[5]) +
                     ", which places no grid; give it one: `gdal_edit.py -a_ullr ULX ULY LRX "
                     "LRY " +
                     path + "`");
  }
  if (gt[2] != 0.0 || gt[4] != 0.0) {
    refuse(path,
           "is a rotated or sheared grid; warp it north-up first: `gdalwarp " + path + " dem.tif`");
  }
  GeoReference& geo = dem.geo;
  southUp = gt[5] > 0.0;
  geo.stepX = gt[1];
  geo.stepY = std::abs(gt[5]);
  geo.originX = gt[0] + 0.5 * gt[1];
  geo.originY = southUp ? gt[3] + (dem.height - 0.5) * gt[5] : gt[3] + 0.5 * gt[5];
  return true;
}

// Address space GDAL needs to open a DEM and PROJ to build its CRS (their
// databases and caches). Below it Debian 12's libraries end the process
// instead of reporting a failed allocation (GDAL aborts in its metadata
// reader, PROJ 9.1 dereferences a null pointer in
// proj_create_geographic_crs; seen under ulimit -v with a few MiB left):
// refused before.
constexpr uint64_t kGdalAddressSpaceBytes = uint64_t{16} << 20;

void requireGdalAddressSpace(const std::string& path, const std::string& what) {
  if (const std::optional<std::string> shortfall =
          addressSpaceShortfall(kGdalAddressSpaceBytes, what)) {
    throw std::runtime_error(path + ": " + *shortfall);
  }
}

// The CRS of a placed grid into dem.geo (and a vertical CRS's unit into
// dem.zUnit*).
void describeCrsOf(const std::string& path, GDALDataset& dataset, const DemLoadOptions& options,
                   RawDem& dem) {
  requireGdalAddressSpace(path, "reading its coordinate reference system");
  const OGRSpatialReference* srs = dataset.GetSpatialRef();
  if (srs != nullptr && !srs->IsEmpty()) {
    describeCrs(path, *srs, options, dem);
    return;
  }
  // A grid with coordinates but no CRS (an ASCII grid without .prj): its
  // coordinates are taken as metres, as every GIS would measure them.
  GeoReference& geo = dem.geo;
  geo.crs = CrsKind::Projected;
  if (options.warn) {
    std::string text =
        path + " has no coordinate reference system: taking its coordinates as metres";
    if (geo.stepX < 0.01 || geo.stepY < 0.01) {
      text += " (its cell size, " + std::to_string(geo.stepX) +
              ", looks like degrees: give it a CRS, e.g. a .prj, or --cell-size)";
    }
    options.warn(text);
  }
}

// The CRS and the metric spacing, found on a thread of their own: PROJ takes
// 15-30 ms to build a CRS from a GeoTIFF's keys and as much to map its centre,
// time in which the caller decodes the samples (docs/performance.md).
struct CrsPart {
  RawDem placed;                         // the description's geo with the CRS filled in, and zUnit*
  std::optional<MetricSpacing> spacing;  // of the whole raster; none when it threw
  std::vector<std::string> warnings;
  bool found = false;  // false: the file could not be opened twice
};

// `gdalName`: what GDAL opened for `path` (gdalFileName).
CrsPart findCrs(const std::string& path, const std::string& gdalName, const std::string& driver,
                RawDem placed) {
  CrsPart part;
  DemLoadOptions collect;
  collect.warn = [&part](const std::string& message) { part.warnings.push_back(message); };
  // GDAL datasets are not shared between threads: this one is its own.
  const char* const drivers[] = {driver.c_str(), nullptr};
  GDALDatasetUniquePtr own(
      GDALDataset::FromHandle(GDALOpenEx(gdalName.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY,
                                         driver.empty() ? nullptr : drivers, nullptr, nullptr)));
  if (!own) {  // it cannot be opened twice: the caller's thread reads the CRS
    part.placed = std::move(placed);
    return part;
  }
  part.found = true;
  describeCrsOf(path, *own, collect, placed);
  try {
    part.spacing = metricSpacing(path, placed.geo, placed.width, placed.height);
  } catch (const InputError&) {
    // Raised again, in its place, when the caller asks for the geometry.
  }
  part.placed = std::move(placed);
  return part;
}

void describeHeights(const std::string& path, const std::string& unitType,
                     const DemLoadOptions& options, RawDem& dem) {
  if (dem.zUnitFromFile) return;  // a vertical CRS said it
  if (unitType.empty()) return;
  dem.zUnitName = unitType;
  if (const std::optional<double> unit = metresPerUnit(unitType)) {
    dem.zUnitM = *unit;
    dem.zUnitFromFile = true;
  } else if (options.warn) {
    options.warn(path + " states its heights in \"" + unitType +
                 "\", a unit aperture does not know: taking them as metres (give --z-scale)");
  }
}

std::optional<double> nodataOf(GDALRasterBand& band, GDALDataType type) {
  int has = 0;
  double value = 0;
  if (type == GDT_Int64) {
    const int64_t v = band.GetNoDataValueAsInt64(&has);
    value = static_cast<double>(v);
  } else if (type == GDT_UInt64) {
    const uint64_t v = band.GetNoDataValueAsUInt64(&has);
    value = static_cast<double>(v);
  } else {
    value = band.GetNoDataValue(&has);
  }
  if (!has) return std::nullopt;
  return value;
}

// A window of the file's rows and columns (rows as the file stores them).
struct FileWindow {
  int column, row, width, height;
};

// The band's nodata value, compared in the sample's own precision, as
// GDAL's masks do: float32 samples against the value rounded to float.
struct NodataValue {
  explicit NodataValue(const std::optional<double>& nodata)
      : present(nodata.has_value() && !std::isnan(*nodata)),
        value(present ? *nodata : 0.0),
        asFloat(present ? static_cast<float>(*nodata) : 0.0f) {}
  bool present;
  double value;
  float asFloat;
};

// Samples that float32 holds exactly, read by GDAL straight into `z`, in
// bands of rows as well: a driver that reports no progress inside one call
// (a VRT of one source) still hears Ctrl-C between bands.
void readFloatHeights(const std::string& path, GDALRasterBand& band, const FileWindow& window,
                      GDALRasterIOExtraArg& extra, float* z) {
  const int w = window.width, h = window.height;
  const int bandRows =
      std::max(1, std::min(h, static_cast<int>((size_t{16} << 20) / (sizeof(float) * w))));
  for (int r = 0; r < h; r += bandRows) {
    const int rows = std::min(bandRows, h - r);
    if (band.RasterIO(GF_Read, window.column, window.row + r, w, rows,
                      z + static_cast<size_t>(r) * w, w, rows, GDT_Float32, 0, 0,
                      &extra) != CE_None) {
      throwReadFailure(path);
    }
    throwIfInterrupted();
  }
}

// Flags the void texels of `dem` (1 in voidMask) and zeroes their heights:
// where the mask or alpha read into voidMask is 0 (maskRead), where the
// height is NaN or infinite, and with compareNodata where it equals the
// nodata value.
void flagVoids(RawDem& dem, bool maskRead, bool compareNodata, float nodata) {
  const size_t texels = dem.texelCount();
  tbb::parallel_for(size_t{0}, texels, size_t{1} << 16, [&](size_t i) {
    const size_t end = std::min(texels, i + (size_t{1} << 16));
    for (; i < end; ++i) {
      const bool isVoid = (maskRead && dem.voidMask[i] == 0) || !std::isfinite(dem.z[i]) ||
                          (compareNodata && dem.z[i] == nodata);
      dem.voidMask[i] = isVoid ? 1 : 0;
      if (isVoid) dem.z[i] = 0.0f;
    }
  });
}

// Turns the rows of a south-up window upside down, so that row 0 is north.
void flipRows(RawDem& dem) {
  const int w = dem.width, h = dem.height;
  for (int r = 0; r < h / 2; ++r) {
    std::swap_ranges(dem.z.begin() + static_cast<ptrdiff_t>(r) * w,
                     dem.z.begin() + static_cast<ptrdiff_t>(r + 1) * w,
                     dem.z.begin() + static_cast<ptrdiff_t>(h - 1 - r) * w);
    std::swap_ranges(dem.voidMask.begin() + static_cast<ptrdiff_t>(r) * w,
                     dem.voidMask.begin() + static_cast<ptrdiff_t>(r + 1) * w,
                     dem.voidMask.begin() + static_cast<ptrdiff_t>(h - 1 - r) * w);
  }
}

// The description with the samples of the window at (column, row) (row 0 =
// north) and the georeference placed at its texel (0, 0); the whole raster's
// metric spacing only for the whole raster.
RawDem placedWindow(const RawDem& description, RawDem samples, int column, int row,
                    bool wholeRaster) {
  RawDem placed = description;
  placed.width = samples.width;
  placed.height = samples.height;
  placed.z = std::move(samples.z);
  placed.voidMask = std::move(samples.voidMask);
  if (!wholeRaster) placed.spacing.reset();
  if (placed.geo.crs != CrsKind::None) {
    placed.geo.originX += column * placed.geo.stepX;
    placed.geo.originY -= row * placed.geo.stepY;
  }
  return placed;
}

}  // namespace

struct DemSource::Impl {
  GDALDatasetUniquePtr dataset;
  GDALRasterBand* band = nullptr;
  GDALDataType type = GDT_Unknown;
  bool signedBytes = false;  // GDAL 3.6 reads int8 TIFFs as bytes marked SIGNEDBYTE
  bool southUp = false;      // rows run south to north in the file
  bool readMask = false;     // a mask band says which samples are void
  // An alpha band (0 = void) of any sample type: GDAL takes only 8- and
  // 16-bit alpha bands as masks, but gdalwarp -dstalpha gives a float32 DEM
  // a float32 alpha band.
  int alphaBand = 0;
  double scale = 1.0, offset = 0.0;
  size_t maxTexels = kMaxDemTexels;
  std::string memoryHint;        // DemLoadOptions::memoryHint
  double peakBytesPerTexel = 0;  // DemLoadOptions::peakBytesPerTexel
  std::string workName;
  std::string bandUnit;  // GDAL's unit type of band 1; empty when silent
  std::string gdalName;  // what GDAL opens for the path (gdalFileName)
  // The CRS, found while the caller reads (findCrs), then merged into the
  // description once (settle); warnings are given then, on the caller's thread.
  std::future<CrsPart> crs;
  std::function<void(const std::string&)> warn;
  std::mutex settling;
  bool settled = false;
  std::exception_ptr failure;

  // Refuses (InputError) a read of w x h texels that does not fit in memory:
  // a window's heights and void mask, or for the whole raster the caller's
  // work on it when that needs more (DemLoadOptions::peakBytesPerTexel).
  void requireMemoryToRead(const std::string& path, int w, int h, bool wholeRaster) const;
  // Samples GDAL can write straight into the heights: exact in float32,
  // unscaled.
  bool readsDirect() const {
    return exactInFloat(type) && !signedBytes && scale == 1.0 && offset == 0.0;
  }
  // The window's heights into dem.z, scale and offset applied, and its voids
  // flagged in dem.voidMask, their heights 0 (flagVoids).
  void readSamples(const std::string& path, const FileWindow& window, const NodataValue& nodata,
                   RawDem& dem) const;
  // Samples of any type through float64, converted to heights; NaN for
  // nodata, which flagVoids then makes a void.
  void readConvertedHeights(const std::string& path, const FileWindow& window,
                            const NodataValue& nodata, GDALRasterIOExtraArg& extra, float* z) const;
  // The band whose zeros are voids (alpha, else the mask), or none.
  GDALRasterBand* voidBand() const;
};

void DemSource::Impl::requireMemoryToRead(const std::string& path, int w, int h,
                                          bool wholeRaster) const {
  const double readBytes = sizeof(float) + sizeof(uint8_t);
  const bool withWork = wholeRaster && peakBytesPerTexel > readBytes;
  const std::string size = std::to_string(w) + " x " + std::to_string(h);
  requireMemory(
      path, static_cast<double>(w) * h * (withWork ? peakBytesPerTexel : readBytes),
      withWork ? workName + " of its " + size + " texels (" + numberText(peakBytesPerTexel) +
                     " bytes per texel)"
               : (wholeRaster ? "its " : "a window of ") + size + " heights and void mask",
      !memoryHint.empty() ? memoryHint
                          : "aal-bake bakes it a tile at a time (--tile-size N --low-memory); for "
                            "the other tools cut it (`gdal_translate -srcwin`) or coarsen it "
                            "(`gdal_translate -outsize 50% 50%`)");
}

void DemSource::Impl::readSamples(const std::string& path, const FileWindow& window,
                                  const NodataValue& nodata, RawDem& dem) const {
  // Stops at the next block once Ctrl-C or SIGTERM came (terrain/interrupt.h).
  GDALRasterIOExtraArg extra = interruptibleRead();
  const bool direct = readsDirect();
  CPLErrorReset();
  if (direct) {
    readFloatHeights(path, *band, window, extra, dem.z.data());
  } else {
    readConvertedHeights(path, window, nodata, extra, dem.z.data());
  }
  // Mask or alpha as bytes, 0 = void (alpha rounds to the nearest byte).
  GDALRasterBand* mask = voidBand();
  if (mask != nullptr && mask->RasterIO(GF_Read, window.column, window.row, window.width,
                                        window.height, dem.voidMask.data(), window.width,
                                        window.height, GDT_Byte, 0, 0, &extra) != CE_None) {
    throwReadFailure(path);
  }
  flagVoids(dem, mask != nullptr, direct && nodata.present, nodata.asFloat);
}

void DemSource::Impl::readConvertedHeights(const std::string& path, const FileWindow& window,
                                           const NodataValue& nodata, GDALRasterIOExtraArg& extra,
                                           float* z) const {
  // float64 through a band of rows: integers past 2^24 and scale/offset
  // in double precision, then rounded once to float.
  const int w = window.width, h = window.height;
  const int bandRows =
      std::max(1, std::min(h, static_cast<int>((size_t{32} << 20) / (sizeof(double) * w))));
  std::vector<double> samples(static_cast<size_t>(bandRows) * w);
  for (int r = 0; r < h; r += bandRows) {
    const int rows = std::min(bandRows, h - r);
    if (band->RasterIO(GF_Read, window.column, window.row + r, w, rows, samples.data(), w, rows,
                       GDT_Float64, 0, 0, &extra) != CE_None) {
      throwReadFailure(path);
    }
    throwIfInterrupted();
    float* out = z + static_cast<size_t>(r) * w;
    const size_t count = static_cast<size_t>(rows) * w;
    tbb::parallel_for(size_t{0}, count, size_t{1} << 16, [&](size_t i) {
      const size_t end = std::min(count, i + (size_t{1} << 16));
      for (; i < end; ++i) {
        double v = samples[i];
        if (signedBytes && v >= 128.0) v -= 256.0;
        const bool isNodata =
            nodata.present &&
            (type == GDT_Float32 ? static_cast<float>(v) == nodata.asFloat : v == nodata.value);
        out[i] = isNodata ? std::numeric_limits<float>::quiet_NaN()
                          : static_cast<float>(v * scale + offset);
      }
    });
  }
}

GDALRasterBand* DemSource::Impl::voidBand() const {
  if (alphaBand > 0) return dataset->GetRasterBand(alphaBand);
  return readMask ? band->GetMaskBand() : nullptr;
}

DemSource::DemSource(const std::string& path, const DemLoadOptions& options)
    : path_(path), impl_(std::make_unique<Impl>()) {
  // Files only, looked at before GDAL opens them: a FIFO would block the
  // open forever, a connection string (MEM:::DATAPOINTER=...) read memory.
  impl_->gdalName = gdalFileName(path, options.inMemoryFiles);
  requireGdalAddressSpace(path, "opening it");
  impl_->dataset = openDataset(path, impl_->gdalName);
  GDALDataset& dataset = *impl_->dataset;
  impl_->maxTexels = options.maxTexels;
  impl_->memoryHint = options.memoryHint;
  impl_->peakBytesPerTexel = options.peakBytesPerTexel;
  impl_->workName = options.workName;
  const int bands = dataset.GetRasterCount();
  if (bands == 0) {
    const std::string subdatasets = subdatasetList(dataset);
    refuse(path, subdatasets.empty() ? "has no raster band" : "holds " + subdatasets);
  }
  GDALRasterBand& band = *dataset.GetRasterBand(1);
  impl_->band = &band;
  impl_->type = band.GetRasterDataType();
  const GDALColorInterp colour = band.GetColorInterpretation();
  if (GDALDataTypeIsComplex(impl_->type)) {
    refuse(path, "has complex samples (" + sampleTypeName(impl_->type, false) + "), not heights; " +
                     oneBandHint(path));
  }
  if (band.GetColorTable() != nullptr || colour == GCI_PaletteIndex) {
    refuse(path, "is a palette image: its samples index colours, they are not heights; " +
                     oneBandHint(path));
  }
  int alphaBands = 0;
  for (int i = 2; i <= bands; ++i) {
    if (dataset.GetRasterBand(i)->GetColorInterpretation() == GCI_AlphaBand) {
      ++alphaBands;
      if (impl_->alphaBand == 0) impl_->alphaBand = i;
    }
  }
  const int colourBands = bands - alphaBands;
  if (colourBands >= 3 && (colour == GCI_RedBand || colour == GCI_YCbCr_YBand ||
                           colour == GCI_HueBand || colour == GCI_CyanBand)) {
    refuse(path, "is a colour (RGB) image, not heights; " + oneBandHint(path));
  }
  if (colourBands > 1 && options.warn) {
    options.warn(path + " has " + std::to_string(colourBands) +
                 " bands; heights are read from band 1 (`gdal_translate -b N` takes another)");
  }
  checkDemSize(path, dataset.GetRasterXSize(), dataset.GetRasterYSize(), options.maxTexels);
  checkDeclaredSizeFitsTheFile(path, dataset, band);

  RawDem& d = description_;
  d.width = dataset.GetRasterXSize();
  d.height = dataset.GetRasterYSize();
  GDALDriver* driver = dataset.GetDriver();
  d.driver = driver != nullptr ? driver->GetDescription() : "";
  const char* longName = driver != nullptr ? driver->GetMetadataItem(GDAL_DMD_LONGNAME) : nullptr;
  d.format = longName != nullptr ? longName : d.driver;
  const char* pixelType = band.GetMetadataItem("PIXELTYPE", "IMAGE_STRUCTURE");
  impl_->signedBytes =
      impl_->type == GDT_Byte && pixelType != nullptr && std::strcmp(pixelType, "SIGNEDBYTE") == 0;
  d.sampleType = sampleTypeName(impl_->type, impl_->signedBytes);
  d.nodata = nodataOf(band, impl_->type);
  int hasScale = 0, hasOffset = 0;
  const double scale = band.GetScale(&hasScale), offset = band.GetOffset(&hasOffset);
  if ((hasScale && !std::isfinite(scale)) || (hasOffset && !std::isfinite(offset))) {
    refuse(path,
           "has a band scale of " + numberText(scale) + " and offset of " + numberText(offset) +
               ", which give no heights; fix them: `gdal_edit.py -scale 1 -offset 0 " + path + "`");
  }
  if (hasScale && scale == 0.0) {
    // Some writers store 0 for "no scale"; taken at its word it would make
    // every height equal to the offset.
    if (options.warn) {
      options.warn(path +
                   " has a band scale of 0, which would flatten every height: taken as 1 (no "
                   "scale); if that is wrong, set the right one with `gdal_edit.py -scale S " +
                   path + "`");
    }
  } else if (hasScale) {
    impl_->scale = scale;
  }
  if (hasOffset) impl_->offset = offset;
  const int maskFlags = band.GetMaskFlags();
  impl_->readMask =
      impl_->alphaBand == 0 && (maskFlags & GMF_ALL_VALID) == 0 && maskFlags != GMF_NODATA;
  const char* unitType = band.GetUnitType();
  impl_->bandUnit = unitType != nullptr ? unitType : "";
  impl_->warn = options.warn;
  if (describeTransform(path, dataset, d, impl_->southUp)) {
    impl_->crs = std::async(std::launch::async, findCrs, path, impl_->gdalName, d.driver, d);
  }
}

DemSource::~DemSource() = default;

void DemSource::settle() const {
  const std::lock_guard<std::mutex> lock(impl_->settling);
  if (impl_->settled) {
    if (impl_->failure) std::rethrow_exception(impl_->failure);
    return;
  }
  impl_->settled = true;
  try {
    RawDem& d = description_;
    DemLoadOptions options;
    options.warn = impl_->warn;
    if (impl_->crs.valid()) {
      CrsPart part = impl_->crs.get();
      if (!part.found) describeCrsOf(path_, *impl_->dataset, options, part.placed);
      if (options.warn) {
        for (const std::string& message : part.warnings) options.warn(message);
      }
      d.geo = part.placed.geo;
      d.zUnitM = part.placed.zUnitM;
      d.zUnitFromFile = part.placed.zUnitFromFile;
      d.zUnitName = part.placed.zUnitName;
      d.spacing = std::move(part.spacing);
    }
    describeHeights(path_, impl_->bandUnit, options, d);
  } catch (...) {
    impl_->failure = std::current_exception();
    throw;
  }
}

const RawDem& DemSource::description() const {
  settle();
  return description_;
}

RawDem DemSource::read(int column, int row, int w, int h) const {
  const RawDem& whole = description_;
  if (column < 0 || row < 0 || w < 1 || h < 1 || column > whole.width - w ||
      row > whole.height - h) {
    throw std::invalid_argument("DemSource::read: window outside the raster");
  }
  checkDemSize(path_, w, h, impl_->maxTexels);
  const bool wholeRaster = w == whole.width && h == whole.height;
  impl_->requireMemoryToRead(path_, w, h, wholeRaster);
  RawDem dem;  // the samples; the description joins them at the end
  dem.allocate(w, h);
  texelsRead_ += static_cast<uint64_t>(w) * static_cast<uint64_t>(h);
  const int fileRow = impl_->southUp ? whole.height - row - h : row;
  impl_->readSamples(path_, {column, fileRow, w, h}, NodataValue(whole.nodata), dem);
  if (impl_->southUp) flipRows(dem);
  // The CRS was found meanwhile (findCrs); the window is placed in it.
  settle();
  return placedWindow(description_, std::move(dem), column, row, wholeRaster);
}

}  // namespace aal
