#include "aperture/terrain/io/raster_files.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <cpl_string.h>
#include <gdal_priv.h>

#include "aperture/terrain/io/gdal_session.h"

namespace aal {

namespace fs = std::filesystem;

namespace {

// Nested VRTs deeper than this are not followed (GDAL itself refuses
// recursion beyond a few levels).
constexpr int kMaxVrtDepth = 8;

bool isVrt(const std::string& path) {
  std::string extension = fs::path(path).extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".vrt";
}

// GDAL's file list of `path`, or nothing when it is not a regular file or
// GDAL does not open it.
std::vector<std::string> fileListOf(const std::string& path) {
  std::error_code error;
  if (!fs::is_regular_file(path, error)) return {};
  // Most DEMs are GeoTIFFs: their driver alone, without registering all.
  GDALDatasetUniquePtr dataset = openGeoTiff(path);
  if (!dataset) {
    ensureGdal();
    dataset.reset(GDALDataset::FromHandle(
        GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr)));
  }
  if (!dataset) return {};
  std::vector<std::string> files;
  char** list = dataset->GetFileList();
  for (char** file = list; file != nullptr && *file != nullptr; ++file) files.emplace_back(*file);
  CSLDestroy(list);
  return files;
}

void collect(const std::string& path, int depth, std::vector<std::string>& files) {
  for (const std::string& file : fileListOf(path)) {
    if (std::find(files.begin(), files.end(), file) != files.end()) continue;
    files.push_back(file);
    // GDAL lists a VRT's sources but not the sources of a VRT among them.
    if (depth < kMaxVrtDepth && file != path && isVrt(file)) collect(file, depth + 1, files);
  }
}

}  // namespace

std::vector<std::string> rasterFiles(const std::string& path) {
  std::vector<std::string> files{path};
  collect(path, 0, files);
  return files;
}

}  // namespace aal
