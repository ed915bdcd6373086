// How an aperture map's EXR chunks are compressed.
#pragma once

namespace aal {

// On this project's maps (halves of noisy normals) zlib gains little and
// costs much: a 4096^2 half map writes in 3.3 s as ZIP (79 MB), 0.64 s as RLE
// (108 MB), 0.23 s uncompressed (134 MB) on 2 cores (docs/performance.md).
// Every EXR reader reads each.
enum class MapCompression { Rle, Zip, None };
constexpr MapCompression kDefaultMapCompression = MapCompression::Rle;

}  // namespace aal
