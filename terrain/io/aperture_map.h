// Aperture map: per texel the visible sky as a spherical cap — the unit bent
// normal (mean unoccluded direction, world frame x east, y north, z up) and
// the cap's arc length r = acos(1 - visible solid angle / 2 pi). docs/design.md §3-4.
//
// On disk: OpenEXR, same size as the DEM, channels R, G, B = bent normal,
// A = arc length in radians, with `aal:` header attributes that tie the map
// to its DEM and bake options. Or a GeoTIFF of the same four bands
// (terrain/io/aperture_geotiff.h), which every reader below takes alike.
//
// A tiled bake writes a folder instead: one such EXR per tile, named
// tile_ROW_COL.exr (tile indices, 4 digits) with its place in the DEM in
// aal:tileOrigin, and index.txt, written last, with the full size, the tile
// size and the bake's attributes. Everything below that reads a map also
// reads such a folder, as one map (docs/baking.md).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/heightfield_checksum.h"
#include "aperture/terrain/io/map_compression.h"

namespace aal {

struct ApertureMapInfo {
  int version = 1;
  int azimuths = 0;
  std::string method;  // "sweep" or "rays"
  double cellSizeX = 0, cellSizeY = 0, zScale = 1;
  std::string source;  // file name of the DEM (no folder)
  int sourceWidth = 0, sourceHeight = 0;
  std::string sourceChecksum;  // heightfieldChecksum() of the DEM (heightfield_checksum.h)
  std::string edge = "open";   // "open" or "clamp"
  bool curvature = false;
  double refraction = 0;    // used when curvature is on
  double maxDistanceM = 0;  // 0 = unlimited
  // Where this map's texel (0, 0) lies in the source: 0, 0 but for the
  // tiles of a tiled bake (aal:tileOrigin, written when the map is a part).
  int originCol = 0, originRow = 0;
  // What wrote the file, softwareName() (terrain/version.h) as read back
  // (aal:software; a folder's index "software"); "" in files older than it.
  // A writer records its own softwareName(), whatever this says.
  std::string software;
};

struct ApertureMap {
  int width = 0, height = 0;
  std::vector<float> texels;  // 4 floats per texel: bent normal x, y, z; arc length
  ApertureMapInfo info;

  size_t texelCount() const { return static_cast<size_t>(width) * static_cast<size_t>(height); }
  // Visible solid angle over 2 pi, in [0, 1]: 1 - cos r.
  float visibleFraction(size_t texel) const;
};

// Writes the map as EXR via a temporary file renamed into place. halfFloat
// stores 16-bit floats (bent normal to ~1e-3, arc length to ~1e-3 rad). The
// header carries aal:pixelChecksum, the checksum of the pixels as stored
// (pixel_checksum.h).
void writeApertureMap(const std::string& path, const ApertureMap& map, bool halfFloat,
                      MapCompression compression = kDefaultMapCompression);

struct ApertureMapHeader {
  int width = 0, height = 0;
  ApertureMapInfo info;
  // aal:pixelChecksum; maps written before it existed have none (nor has a
  // tiled map's folder: each tile has its own).
  std::optional<uint64_t> pixelChecksum;
};

// Reads a map written by writeApertureMap, a GeoTIFF map (.tif, .tiff:
// writeApertureGeoTiff, terrain/io/aperture_geotiff.h, read through GDAL),
// or a tiled map's folder (whole).
// Throws InputError naming the file when it is missing, unreadable, not 4
// channels or lacks the aal: attributes, when its pixels do not match its
// aal:pixelChecksum, or when a tile does not belong to its folder's index.
ApertureMap readApertureMap(const std::string& path);

// The index of a tiled map (index.txt in its folder).
struct ApertureTileIndex {
  ApertureMapHeader map;  // the whole map: full size, the bake's attributes
  int tileSize = 0;       // tiles are tileSize square, less at the right and bottom edges
  // The folder also holds the sky-view factor (a GeoTIFF per tile and a VRT
  // mosaic, preprocess/sky_view_factor_tiles.h). Indexes written before it
  // was recorded say nothing: false.
  bool skyViewFactor = false;

  int columns() const { return (map.width + tileSize - 1) / tileSize; }
  int rows() const { return (map.height + tileSize - 1) / tileSize; }
  int tileWidth(int column) const { return std::min(tileSize, map.width - column * tileSize); }
  int tileHeight(int row) const { return std::min(tileSize, map.height - row * tileSize); }
};

// "tile_0002_0013.exr" for tile row 2, column 13.
std::string apertureTileName(int row, int column);
// index.txt in `folder`, written via a temporary file renamed into place;
// `name` another file of the same format (a tiled bake's manifest.txt).
void writeApertureTileIndex(const std::string& folder, const ApertureTileIndex& index,
                            const std::string& name = "index.txt");
// Throws InputError naming the folder when index.txt (or `name`) is
// missing or malformed.
ApertureTileIndex readApertureTileIndex(const std::string& folder,
                                        const std::string& name = "index.txt");
// Throws InputError naming the tile's file unless the header is that of
// tile (row, column) of `index` (size, origin, DEM checksum, attributes).
void checkApertureTile(const ApertureTileIndex& index, int row, int column,
                       const ApertureMapHeader& tile, const std::string& tilePath);

// Streams a map row band by row band, so that large maps never sit in memory
// as floats: the renderer copies them straight into staging memory. A tiled
// map's folder reads the same: the rows are put together from its tiles.
class ApertureMapReader {
 public:
  // Opens and validates the header (errors as readApertureMap); for a
  // folder, its index (tiles are opened as their rows are read).
  explicit ApertureMapReader(const std::string& path);
  ~ApertureMapReader();
  ApertureMapReader(const ApertureMapReader&) = delete;
  ApertureMapReader& operator=(const ApertureMapReader&) = delete;

  const ApertureMapHeader& header() const { return header_; }
  // Rows [firstRow, endRow) as RGBA 16-bit halves, tightly packed (8 bytes
  // per texel). Throws InputError when the file is truncated or corrupt, and
  // with the read that completes the map's rows (in any order and bands)
  // when they do not match aal:pixelChecksum.
  void readHalfRows(int firstRow, int endRow, void* destination);
  // Reads every row once for the checks of readHalfRows alone (a map
  // without aal:pixelChecksum is only decoded).
  void verify();

 private:
  struct Impl;
  std::string path_;
  ApertureMapHeader header_;
  Impl* impl_ = nullptr;
};

// Throws InputError naming both files when the map was not baked from this
// DEM (size, checksum).
void checkApertureMatchesDem(const ApertureMapHeader& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath);
void checkApertureMatchesDem(const ApertureMap& map, const std::string& mapPath,
                             const Heightfield& field, const std::string& demPath);

}  // namespace aal
