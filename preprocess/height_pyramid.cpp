#include "aperture/preprocess/height_pyramid.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace aal {

namespace {

int blocks(int texels, int shift) {
  return ((texels - 1) >> shift) + 1;
}

// Texels of block b along an axis of `texels` texels.
int blockSpan(int b, int shift, int texels) {
  return std::min(texels, (b + 1) << shift) - (b << shift);
}

}  // namespace

HeightPyramid::HeightPyramid(int width, int height, int baseShift)
    : width_(width), height_(height) {
  if (width < 1 || height < 1 || baseShift < 0 || baseShift > 30) {
    throw std::invalid_argument("height pyramid: bad size or base shift");
  }
  for (int shift = baseShift;; ++shift) {
    Level level;
    level.shift = shift;
    level.width = blocks(width, shift);
    level.height = blocks(height, shift);
    levels_.push_back(std::move(level));
    if (levels_.back().width == 1 && levels_.back().height == 1) break;
  }
  Level& base = levels_.front();
  base.max.assign(static_cast<size_t>(base.width) * base.height,
                  -std::numeric_limits<float>::infinity());
  base.mean.assign(base.max.size(), 0.0f);
  rowSums_.assign(static_cast<size_t>(base.width), 0.0);
  filled_.assign(static_cast<size_t>(base.height), 0);
}

void HeightPyramid::addRows(const float* rows, int count) {
  if (count < 0 || rowsAdded_ + count > height_) {
    throw std::invalid_argument("height pyramid: more rows than the DEM has");
  }
  if (rowsAdded_ == 0 && filledBlockRows_ > 0) {
    throw std::invalid_argument("height pyramid: rows in order after block rows");
  }
  Level& base = levels_.front();
  for (int i = 0; i < count; ++i) {
    const int row = rowsAdded_ + i;
    const int blockRow = row >> base.shift;
    const float* z = rows + static_cast<size_t>(i) * width_;
    float* max = base.max.data() + static_cast<size_t>(blockRow) * base.width;
    for (int col = 0; col < width_; ++col) {
      const int bx = col >> base.shift;
      max[bx] = std::max(max[bx], z[col]);
      rowSums_[bx] += z[col];
    }
    if (row + 1 == height_ || ((row + 1) & ((1 << base.shift) - 1)) == 0) finishBlockRow(blockRow);
  }
  rowsAdded_ += count;
  if (complete()) buildCoarserLevels();
}

void HeightPyramid::addBlockRows(int firstRow, const float* rows, int count) {
  Level& base = levels_.front();
  const int blockTexels = 1 << base.shift;
  if (rowsAdded_ != 0 || firstRow < 0 || count < 1 || firstRow + count > height_ ||
      firstRow % blockTexels != 0 || (count % blockTexels != 0 && firstRow + count != height_)) {
    throw std::invalid_argument("height pyramid: rows " + std::to_string(firstRow) + " + " +
                                std::to_string(count) + " are not whole block rows");
  }
  const int firstBlock = firstRow >> base.shift;
  const int blockRows = blocks(count, base.shift);
  markFilled(firstBlock, blockRows);
  // Each block row as addRows makes it: rows in order, columns in order,
  // the sums in doubles, so the means are the same floats.
  tbb::parallel_for(tbb::blocked_range<int>(0, blockRows), [&](const tbb::blocked_range<int>& r) {
    std::vector<double> sums(static_cast<size_t>(base.width));
    for (int b = r.begin(); b < r.end(); ++b) {
      const int blockRow = firstBlock + b;
      const int spanY = blockSpan(blockRow, base.shift, height_);
      float* max = base.max.data() + static_cast<size_t>(blockRow) * base.width;
      std::fill(sums.begin(), sums.end(), 0.0);
      for (int i = 0; i < spanY; ++i) {
        const float* z = rows + static_cast<size_t>(b * blockTexels + i) * width_;
        for (int col = 0; col < width_; ++col) {
          const int bx = col >> base.shift;
          max[bx] = std::max(max[bx], z[col]);
          sums[static_cast<size_t>(bx)] += z[col];
        }
      }
      float* mean = base.mean.data() + static_cast<size_t>(blockRow) * base.width;
      for (int bx = 0; bx < base.width; ++bx) {
        const double texels = double(blockSpan(bx, base.shift, width_)) * spanY;
        mean[bx] = static_cast<float>(sums[static_cast<size_t>(bx)] / texels);
      }
    }
  });
  if (complete()) buildCoarserLevels();
}

void HeightPyramid::setBaseBlockRows(int firstBlockRow, int count, const float* max,
                                     const float* mean) {
  if (rowsAdded_ != 0) throw std::invalid_argument("height pyramid: rows were added already");
  Level& base = levels_.front();
  markFilled(firstBlockRow, count);
  const size_t first = static_cast<size_t>(firstBlockRow) * base.width;
  const size_t floats = static_cast<size_t>(count) * base.width;
  std::copy(max, max + floats, base.max.begin() + static_cast<std::ptrdiff_t>(first));
  std::copy(mean, mean + floats, base.mean.begin() + static_cast<std::ptrdiff_t>(first));
  if (complete()) buildCoarserLevels();
}

void HeightPyramid::markFilled(int first, int count) {
  const int blockRows = levels_.front().height;
  if (complete()) throw std::invalid_argument("height pyramid: every block row is filled");
  if (first < 0 || count < 0 || first + count > blockRows) {
    throw std::invalid_argument("height pyramid: block rows outside the finest level");
  }
  for (int b = first; b < first + count; ++b) {
    if (filled_[static_cast<size_t>(b)]) {
      throw std::invalid_argument("height pyramid: block row " + std::to_string(b) +
                                  " filled twice");
    }
  }
  std::fill(filled_.begin() + first, filled_.begin() + first + count, char{1});
  filledBlockRows_ += count;
}

void HeightPyramid::finishBlockRow(int blockRow) {
  markFilled(blockRow, 1);
  Level& base = levels_.front();
  const int spanY = blockSpan(blockRow, base.shift, height_);
  for (int bx = 0; bx < base.width; ++bx) {
    const double texels = double(blockSpan(bx, base.shift, width_)) * spanY;
    base.mean[static_cast<size_t>(blockRow) * base.width + bx] =
        static_cast<float>(rowSums_[bx] / texels);
    rowSums_[bx] = 0.0;
  }
}

void HeightPyramid::buildCoarserLevels() {
  rowSums_ = {};
  filled_ = {};
  for (size_t l = 1; l < levels_.size(); ++l) {
    const Level& fine = levels_[l - 1];
    Level& coarse = levels_[l];
    coarse.max.assign(static_cast<size_t>(coarse.width) * coarse.height, 0.0f);
    coarse.mean.assign(coarse.max.size(), 0.0f);
    for (int by = 0; by < coarse.height; ++by) {
      for (int bx = 0; bx < coarse.width; ++bx) {
        float max = -std::numeric_limits<float>::infinity();
        double sum = 0.0, texels = 0.0;
        for (int fy = 2 * by; fy < std::min(2 * by + 2, fine.height); ++fy) {
          for (int fx = 2 * bx; fx < std::min(2 * bx + 2, fine.width); ++fx) {
            const double n =
                double(blockSpan(fx, fine.shift, width_)) * blockSpan(fy, fine.shift, height_);
            max = std::max(max, fine.maxAt(fx, fy));
            sum += n * fine.meanAt(fx, fy);
            texels += n;
          }
        }
        coarse.max[static_cast<size_t>(by) * coarse.width + bx] = max;
        coarse.mean[static_cast<size_t>(by) * coarse.width + bx] = static_cast<float>(sum / texels);
      }
    }
  }
}

size_t HeightPyramid::bytes() const {
  size_t total = 0;
  for (const Level& level : levels_)
    total += (level.max.size() + level.mean.size()) * sizeof(float);
  return total;
}

HeightPyramid buildHeightPyramid(const Heightfield& field, int baseShift) {
  if (field.z.size() != field.texelCount()) {
    throw std::invalid_argument("height pyramid: the field must hold all its texels");
  }
  HeightPyramid pyramid(field.width, field.height, baseShift);
  pyramid.addRows(field.z.data(), field.height);
  return pyramid;
}

int pyramidBaseShift(double startM, double largestCellM, int resolution) {
  const double block = startM / (resolution * largestCellM);  // in cells
  return block < 2.0 ? 0 : std::min(30, static_cast<int>(std::floor(std::log2(block))));
}

}  // namespace aal
