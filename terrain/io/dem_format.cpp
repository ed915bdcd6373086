#include "dem_format.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "errors.h"

namespace aal {

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool startsWith(const std::string& bytes, std::string_view magic) {
  return bytes.size() >= magic.size() && bytes.compare(0, magic.size(), magic) == 0;
}

bool looksLikeAsciiGrid(const std::string& head) {
  size_t start = 0;
  while (start < head.size() && std::isspace(static_cast<unsigned char>(head[start]))) ++start;
  std::string word;
  for (size_t i = start; i < head.size() && std::isalpha(static_cast<unsigned char>(head[i]));
       ++i) {
    word += static_cast<char>(std::tolower(static_cast<unsigned char>(head[i])));
  }
  for (const char* key :
       {"ncols", "nrows", "xllcorner", "xllcenter", "yllcorner", "yllcenter", "cellsize"}) {
    if (word == key) return true;
  }
  return false;
}

}  // namespace

DemFormat detectDemFormat(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (!fs::exists(status)) throw InputError(path + ": no such file");
  if (fs::is_directory(status)) throw InputError(path + ": is a folder, not a DEM file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open: " + std::strerror(errno));
  std::string head(64, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  if (head.empty()) throw InputError(path + ": file is empty");

  using namespace std::string_view_literals;
  if (startsWith(head, "II*\0"sv) || startsWith(head, "MM\0*"sv) || startsWith(head, "II+\0"sv) ||
      startsWith(head, "MM\0+"sv)) {
    return DemFormat::GeoTiff;
  }
  const std::string ext = lowerExtension(path);
  // SRTM tiles have no header; their extension is all there is.
  if (ext == ".hgt") return DemFormat::Hgt;
  if (startsWith(head, "\x76\x2f\x31\x01"sv)) return DemFormat::OpenExr;
  if (startsWith(head, "\x89PNG\r\n\x1a\n"sv)) return DemFormat::Png;
  if (looksLikeAsciiGrid(head) || ext == ".asc") return DemFormat::AsciiGrid;
  throw InputError(path + ": unrecognised DEM format (expected " +
                   "GeoTIFF/TIFF, SRTM .hgt, ESRI ASCII grid .asc, PNG or OpenEXR)");
}

std::string demFormatsHelp() {
  return "DEM formats (detected from the content; .hgt from the extension):\n"
         "  GeoTIFF / TIFF   int8..int32, uint8..uint32, float16/32/64; strips or tiles;\n"
         "                   compressed; georeferenced by GeoKeys, GDAL_NODATA voids\n"
         "  SRTM .hgt        1201x1201 (3\") or 3601x3601 (1\"), position from the name\n"
         "  ESRI ASCII grid  .asc with ncols/nrows/xll*/yll*/cellsize, optional .prj\n"
         "  PNG, OpenEXR     8/16-bit or float heights, first channel, not georeferenced\n";
}

}  // namespace aal
