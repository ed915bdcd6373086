#include "aperture/preprocess/tile_window_reader.h"

#include <algorithm>
#include <cstring>
#include <utility>
#include <vector>

#include "aperture/terrain/io/dem_loader.h"
#include "aperture/terrain/io/dem_source.h"

namespace aal {

TexelWindow tileReadWindow(const Heightfield& geometry, int halo, const TexelWindow& tile) {
  const int left = std::max(0, tile.col - halo), top = std::max(0, tile.row - halo);
  const int right = std::min(geometry.width, tile.col + tile.width + halo);
  const int bottom = std::min(geometry.height, tile.row + tile.height + halo);
  return TexelWindow{left, top, right - left, bottom - top};
}

TileWindowReader::TileWindowReader(const DemSource& source, const Heightfield& geometry, int halo)
    : source_(source), geometry_(geometry), halo_(halo) {
  window_.dem = &geometry;
}

void TileWindowReader::readColumns(const TexelWindow& want, int col, int columns,
                                   std::vector<float>& z) {
  if (columns <= 0) return;
  const HeightWindow part = readDemWindow(source_, geometry_, col, want.row, columns, want.height);
  texelsRead_ += part.z.size();
  const size_t offset = static_cast<size_t>(col - want.col);
  for (int r = 0; r < want.height; ++r) {
    std::memcpy(z.data() + static_cast<size_t>(r) * want.width + offset,
                part.z.data() + static_cast<size_t>(r) * columns, sizeof(float) * columns);
  }
}

const HeightWindow& TileWindowReader::windowFor(const TexelWindow& tile) {
  const TexelWindow want = tileReadWindow(geometry_, halo_, tile);
  const TexelWindow& held = window_.texels;
  if (held.width > 0 && held.col == want.col && held.row == want.row && held.width == want.width &&
      held.height == want.height) {
    return window_;
  }
  std::vector<float> z(want.texelCount());
  // The columns both windows hold, kept when the rows are the same.
  int keepFirst = want.col, keepEnd = want.col;
  if (held.width > 0 && held.row == want.row && held.height == want.height) {
    keepFirst = std::max(want.col, held.col);
    keepEnd = std::min(want.col + want.width, held.col + held.width);
    if (keepFirst >= keepEnd) keepFirst = keepEnd = want.col;
  }
  for (int r = 0; r < want.height && keepFirst < keepEnd; ++r) {
    std::memcpy(z.data() + static_cast<size_t>(r) * want.width + (keepFirst - want.col),
                window_.z.data() + static_cast<size_t>(r) * held.width + (keepFirst - held.col),
                sizeof(float) * (keepEnd - keepFirst));
  }
  readColumns(want, want.col, keepFirst - want.col, z);
  readColumns(want, keepEnd, want.col + want.width - keepEnd, z);
  window_.z = std::move(z);
  window_.texels = want;
  return window_;
}

}  // namespace aal
