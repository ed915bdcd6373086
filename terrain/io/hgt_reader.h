// SRTM .hgt tiles: 1201 x 1201 (3 arc-second) or 3601 x 3601 (1 arc-second)
// big-endian int16 heights in metres, void = -32768, geographic WGS84. The
// file name (N36W085.hgt) is the centre of the south-west sample, i.e. the
// samples are points (DESIGN §11).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>

#include "dem_options.h"
#include "raw_dem.h"

namespace aal {

constexpr int kHgtVoid = -32768;

struct HgtTileName {
  int southLatDeg = 0;  // latitude of the southern row, [-90, 89]
  int westLonDeg = 0;   // longitude of the western column, [-180, 179]
};

// Parses the tile position from a file name: N|S two digits, E|W three
// digits, case-insensitive, anything may follow ("N36W085.hgt",
// "n36w085.SRTMGL1.hgt"). Folders in `fileName` are ignored. Empty when the
// name has another shape; throws InputError("PATH: ...") when it has the
// shape but names no valid tile (N90, E180, S91, ...).
std::optional<HgtTileName> parseHgtTileName(const std::string& path);

// Decodes a whole .hgt file held in memory; `path` names it (and gives the
// tile position). A name without a position gives an ungeoreferenced DEM and
// a warning. Throws InputError("PATH: ...") unless bytes.size() is
// 2 * 1201^2 or 2 * 3601^2.
RawDem parseHgt(const std::string& path, std::span<const uint8_t> bytes,
                const DemLoadOptions& options);

// Reads and decodes PATH (size checked before reading).
RawDem readHgt(const std::string& path, const DemLoadOptions& options);

}  // namespace aal
