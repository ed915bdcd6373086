// Filling void (nodata) texels for geometry: each void texel takes the height
// of its nearest valid texel (docs/design.md §3).
#pragma once

#include <cstdint>
#include <vector>

namespace aal {

// Replaces every texel flagged in `voidMask` (1 = void; width * height
// entries, row-major) by the height of the nearest valid texel, with
// distances measured in metres (cellSizeXM, cellSizeYM > 0) so that
// anisotropic geographic cells are handled. Nearest is found with the
// two-pass 8-neighbour sequential Euclidean distance transform (Danielsson
// 1980, "Euclidean distance mapping"), which is exact except for rare ties
// within a fraction of a cell. Valid texels are left untouched. Returns false
// (and changes nothing) when there is no valid texel at all. An empty mask
// means no voids. Throws std::invalid_argument when the sizes disagree or
// width * height >= 2^32 - 1.
bool fillVoidsNearest(std::vector<float>& z, const std::vector<uint8_t>& voidMask, int width,
                      int height, double cellSizeXM, double cellSizeYM);

}  // namespace aal
