#include "aperture/terrain/io/raw_dem.h"

#include "aperture/terrain/errors.h"
#include "aperture/terrain/huge_pages.h"

namespace aal {

void RawDem::allocate(int w, int h) {
  width = w;
  height = h;
  // Gigabytes for big DEMs: 2 MiB pages made on all threads (huge_pages.h)
  // instead of one 4 KiB page fault at a time as GDAL first writes them.
  assignOnHugePages(z, texelCount(), 0.0f);
  assignOnHugePages(voidMask, texelCount(), uint8_t{0});
}

void checkDemSize(const std::string& path, int64_t width, int64_t height, size_t maxTexels) {
  const std::string size = std::to_string(width) + " x " + std::to_string(height);
  if (width <= 0 || height <= 0) {
    throw InputError(path + ": size " + size + " has no texels");
  }
  if (width > kMaxDemSide || height > kMaxDemSide) {
    throw InputError(path + ": size " + size + " is larger than the limit of " +
                     std::to_string(kMaxDemSide) + " texels per side");
  }
  const size_t texels = static_cast<size_t>(width) * static_cast<size_t>(height);
  if (texels > maxTexels) {
    throw InputError(path + ": size " + size + " has " + std::to_string(texels) +
                     " texels, more than the limit of " + std::to_string(maxTexels));
  }
}

}  // namespace aal
