// Surface albedo from an image (e.g. an orthophoto), at the DEM's size.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace aal {

// Linear RGB albedo in [0, 1], row-major, three floats per texel.
struct AlbedoImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

// Reads any image OpenImageIO can (PNG, JPEG, TIFF, EXR, ...) through the
// image plugin (image_files.h). 8- and 16-bit images are taken as
// sRGB-encoded and linearized; float images as linear. Grey images are
// replicated to RGB; a fourth channel is ignored. When the image's size
// differs from width x height it is resampled (bilinear) and `note` is told
// so. Throws InputError naming the file when it cannot be read, is not a
// regular file (a FIFO, a device: not opened), or its header claims more
// pixels than the memory available holds (memory_budget.h) or, for a PNG,
// than its bytes can hold at zlib's best ratio: checked from the header
// alone, before any pixel is decoded.
AlbedoImage loadAlbedoImage(const std::string& path, int width, int height,
                            const std::function<void(const std::string&)>& note);

}  // namespace aal
