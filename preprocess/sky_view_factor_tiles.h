// A tiled bake's sky-view factor (docs/baking.md, "Tiled bakes"): beside
// each tile's EXR a float32 GeoTIFF of the tile's sky-view factor, placed
// like that window of the DEM, and at the end a GDAL VRT mosaic of them all
// that GIS tools open as one raster placed like the DEM.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "aperture/terrain/height_view.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/aperture_map.h"
#include "aperture/terrain/io/geotiff_writer.h"
#include "aperture/terrain/texel_window.h"

namespace aal {

// The mosaic, in the tile folder.
constexpr const char* kSkyViewFactorMosaicName = "sky_view_factor.vrt";

// "svf_0002_0013.tif" for tile row 2, column 13 (apertureTileName's
// numbering).
std::string skyViewFactorTileName(int row, int column);

// Throws InputError unless a tiled bake of `geometry` can write its
// sky-view factor: the tiles are placed (and mosaicked) by the DEM's
// georeferencing, which it must have. Nothing to check without the SVF.
void checkSkyViewFactorTiles(const Heightfield& geometry, bool skyViewFactor);

// The rule of every per-texel float GeoTIFF a bake writes (--svf,
// --visible, a tiled bake's sky-view factor tiles): the DEM's voids hold
// NaN, the band's nodata value, whatever integer nodata the DEM had (GDAL's
// convention for float rasters; RVT and SAGA read it). `values` are
// `window`'s texels of the DEM, row-major; `heights` (the whole DEM, or a
// window of it holding `window`) gives the voids. Returns that nodata value
// (NaN), which the GeoTIFF declares whether or not there are voids.
std::optional<float> markVoidsAsNodata(std::vector<float>& values, HeightView heights,
                                       const TexelWindow& window);

// GDAL metadata items of a tile's GeoTIFF that tie it to its place and its
// bake, as aal:tileOrigin, aal:sourceChecksum and aal:pixelChecksum tie an
// aperture tile (terrain/io/aperture_map.h); gdalinfo lists them.
constexpr const char* kSvfTileItem = "AAL_TILE";                       // "ROW COLUMN"
constexpr const char* kSvfTileOriginItem = "AAL_TILE_ORIGIN";          // "COLUMN,ROW" in texels
constexpr const char* kSvfSourceSizeItem = "AAL_SOURCE_SIZE";          // "WIDTHxHEIGHT"
constexpr const char* kSvfSourceChecksumItem = "AAL_SOURCE_CHECKSUM";  // the heights checksum
constexpr const char* kSvfBakeItem = "AAL_BAKE";                       // the options, in words
constexpr const char* kSvfPixelChecksumItem = "AAL_PIXEL_CHECKSUM";    // 16 hex digits

// The items of tile (row, column) of `index`'s bake but the pixel checksum.
std::vector<std::pair<std::string, std::string>> skyViewFactorTileItems(
    const ApertureTileIndex& index, int row, int column);

// The pixel checksum of a tile's values as stored (AAL_PIXEL_CHECKSUM): the
// aperture map's (terrain/io/pixel_checksum.h) over the rows of float32s,
// nodata included, each row the bytes of its floats in memory
// (little-endian on every machine aperture builds for).
uint64_t skyViewFactorPixelChecksum(const std::vector<float>& values, int width, int height);

// Writes `values` (the window's texels, row-major) of tile (row, column) of
// `index` as a float32 GeoTIFF FOLDER/svf_ROW_COL.tif placed like `window`
// of the DEM: `heights` (the whole DEM, or a window of it holding `window`)
// give the georeferencing, offset by the window's origin, and the voids,
// which are NaN, the nodata value, as in aal-bake's whole-DEM --svf. It
// carries the band description of skyViewFactorBandLabel,
// skyViewFactorTileItems and the pixel checksum of the values as written.
// `raster`: the creation options (-co) and overviews asked for; its
// format is GTiff (the VRT mosaics plain tiles). Temporary file, renamed.
void writeSkyViewFactorTile(const std::string& folder, const ApertureTileIndex& index, int row,
                            int column, std::vector<float> values, HeightView heights,
                            const TexelWindow& window, const RasterWriteOptions& raster = {});

// Whether tile (row, column)'s GeoTIFF is in the folder as this bake wrote
// it: GDAL reads it as one float32 band of the tile's size, it carries this
// tile's items (skyViewFactorTileItems) and its samples match its
// AAL_PIXEL_CHECKSUM. False (the tile is baked again, as an aperture tile
// that does not verify) when it is missing, not a regular file, unreadable,
// of another shape, without the items (written before tiles carried them)
// or with other pixels. Throws InputError naming the file when its items
// say it is another tile, or of another DEM or options (a file moved or
// copied from its place, as an aperture tile of another place is refused:
// preprocess/tiled_bake.h, tileFinished).
bool skyViewFactorTileFinished(const ApertureTileIndex& index, const std::string& folder, int row,
                               int column);

// FOLDER/sky_view_factor.vrt over every tile's GeoTIFF (all must be there),
// naming them relative to the folder. Temporary file, renamed.
void writeSkyViewFactorMosaic(const ApertureTileIndex& index, const std::string& folder);

}  // namespace aal
