// A tiled bake's sky-view factor (docs/baking.md, "Tiled bakes"): beside
// each tile's EXR a float32 GeoTIFF of the tile's sky-view factor, placed
// like that window of the DEM, and at the end a GDAL VRT mosaic of them all
// that GIS tools open as one raster placed like the DEM.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "aperture/preprocess/bake_terrain.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/aperture_map.h"

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

// The rule of every per-texel GeoTIFF a bake writes (--svf, --visible):
// the DEM's voids hold nodata, the DEM's own nodata value when a float holds
// it, else NaN. `values` are `window`'s texels of `field`, row-major.
// Returns the nodata value, or none when the DEM has neither voids nor a
// nodata value (then nothing is changed).
std::optional<float> markVoidsAsNodata(std::vector<float>& values, const Heightfield& field,
                                       const TexelWindow& window);

// Writes `values` (the window's texels, row-major) as a float32 GeoTIFF
// placed like `window` of the DEM: `field` (the DEM, or a band of its rows
// holding the window) gives the georeferencing, offset by the window's
// origin, and the voids, which are nodata as in aal-bake's whole-DEM --svf
// (the DEM's nodata value when float holds it, else NaN). Temporary file,
// renamed.
void writeSkyViewFactorTile(const std::string& path, std::vector<float> values,
                            const Heightfield& field, const TexelWindow& window);

// Whether tile (row, column)'s GeoTIFF is in the folder and GDAL reads it
// as one float32 band of the tile's size.
bool skyViewFactorTileFinished(const ApertureTileIndex& index, const std::string& folder, int row,
                               int column);

// FOLDER/sky_view_factor.vrt over every tile's GeoTIFF (all must be there),
// naming them relative to the folder. Temporary file, renamed.
void writeSkyViewFactorMosaic(const ApertureTileIndex& index, const std::string& folder);

}  // namespace aal
