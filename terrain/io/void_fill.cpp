#include "aperture/terrain/io/void_fill.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <stdexcept>

namespace aal {

namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// Source texel of each texel so far, and the metric squared distance to it.
class NearestMap {
 public:
  NearestMap(const std::vector<uint8_t>& voidMask, int width, int height, double cellX,
             double cellY)
      : width_(width),
        height_(height),
        cellX2_(cellX * cellX),
        cellY2_(cellY * cellY),
        voidMask_(voidMask) {
    source_.resize(voidMask.size());
    for (size_t i = 0; i < voidMask.size(); ++i) {
      source_[i] = voidMask[i] ? kNone : static_cast<uint32_t>(i);
    }
  }

  // Raster scan top-down then bottom-up; within each row a second pass in the
  // opposite direction carries sources along the row.
  void propagate() {
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        offer(x, y, x - 1, y);
        offer(x, y, x - 1, y - 1);
        offer(x, y, x, y - 1);
        offer(x, y, x + 1, y - 1);
      }
      for (int x = width_ - 1; x >= 0; --x) offer(x, y, x + 1, y);
    }
    for (int y = height_ - 1; y >= 0; --y) {
      for (int x = width_ - 1; x >= 0; --x) {
        offer(x, y, x + 1, y);
        offer(x, y, x + 1, y + 1);
        offer(x, y, x, y + 1);
        offer(x, y, x - 1, y + 1);
      }
      for (int x = 0; x < width_; ++x) offer(x, y, x - 1, y);
    }
  }

  uint32_t source(size_t index) const { return source_[index]; }

 private:
  size_t index(int x, int y) const {
    return static_cast<size_t>(y) * static_cast<size_t>(width_) + static_cast<size_t>(x);
  }

  double distance2(int x, int y, uint32_t source) const {
    const double dx = x - static_cast<double>(source % static_cast<uint32_t>(width_));
    const double dy = y - static_cast<double>(source / static_cast<uint32_t>(width_));
    return dx * dx * cellX2_ + dy * dy * cellY2_;
  }

  // Texel (x, y) adopts the source of neighbour (nx, ny) when it is nearer.
  void offer(int x, int y, int nx, int ny) {
    if (!voidMask_[index(x, y)]) return;  // a valid texel is its own nearest
    if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) return;
    const uint32_t candidate = source_[index(nx, ny)];
    if (candidate == kNone) return;
    uint32_t& current = source_[index(x, y)];
    if (current == kNone || distance2(x, y, candidate) < distance2(x, y, current)) {
      current = candidate;
    }
  }

  int width_, height_;
  double cellX2_, cellY2_;
  const std::vector<uint8_t>& voidMask_;
  std::vector<uint32_t> source_;
};

}  // namespace

bool fillVoidsNearest(std::vector<float>& z, const std::vector<uint8_t>& voidMask, int width,
                      int height, double cellSizeXM, double cellSizeYM) {
  if (voidMask.empty()) return true;
  if (voidMask.size() != z.size() ||
      z.size() != static_cast<size_t>(width) * static_cast<size_t>(height) || z.size() >= kNone) {
    throw std::invalid_argument("fillVoidsNearest: mask and heights must be width * height");
  }
  const auto isVoid = [](uint8_t flag) { return flag != 0; };
  if (std::all_of(voidMask.begin(), voidMask.end(), isVoid)) return false;
  if (std::none_of(voidMask.begin(), voidMask.end(), isVoid)) return true;
  NearestMap nearest(voidMask, width, height, cellSizeXM, cellSizeYM);
  nearest.propagate();
  for (size_t i = 0; i < z.size(); ++i) {
    if (voidMask[i]) z[i] = z[nearest.source(i)];
  }
  return true;
}

}  // namespace aal
