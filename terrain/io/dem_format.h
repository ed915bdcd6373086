// Which DEM format a file holds, from its first bytes (and, for headerless
// SRTM tiles, its extension).
#pragma once

#include <string>

namespace aal {

enum class DemFormat { GeoTiff, Hgt, AsciiGrid, Png, OpenExr };

// Magic bytes win: TIFF "II*\0"/"MM\0*" (and BigTIFF "II+\0"/"MM\0+"),
// OpenEXR 76 2f 31 01, PNG 89 "PNG"; a first word of an ESRI ASCII grid
// header key (ncols, nrows, ...) in any case; then the extension ".hgt"
// (SRTM has no header) and ".asc". Throws InputError("PATH: ...") when the
// file is missing, is a folder, cannot be read, is empty, or is none of
// these.
DemFormat detectDemFormat(const std::string& path);

// One line per supported format, for --help texts.
std::string demFormatsHelp();

}  // namespace aal
