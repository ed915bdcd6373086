// A check of a PNG file's chunk structure before OpenImageIO opens it: a
// truncated PNG makes libpng fail inside OpenImageIO's read callback, which
// leaks (OpenImageIO 2.4) and gives a vague message; a hostile IHDR could ask
// for any size.
#pragma once

#include <string>

#include "dem_options.h"

namespace aal {

// Walks the chunks (length, type, data, CRC): the first must be IHDR, every
// chunk must fit inside the file and IEND must be reached; IHDR's size must
// be within the DEM limits. Chunk contents and CRCs are left to libpng.
// Throws InputError("PATH: ...") on any failure.
void checkPngStructure(const std::string& path, const DemLoadOptions& options);

}  // namespace aal
