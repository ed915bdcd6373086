#include "aperture/preprocess/height_pyramid.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

namespace aal {

namespace {

constexpr float kNoHeight = -std::numeric_limits<float>::infinity();

int blocks(int texels, int shift) {
  return ((texels - 1) >> shift) + 1;
}

// Texels of block b along an axis of `texels` texels.
int blockSpan(int b, int shift, int texels) {
  return std::min(texels, (b + 1) << shift) - (b << shift);
}

std::string systemError(const std::string& what, const std::string& folder) {
  return "far-field pyramid file in " + folder + ": " + what + ": " + std::strerror(errno);
}

// A file in `folder` that no directory names: O_TMPFILE where the file
// system has it, else a named one unlinked at once.
int openUnnamedFile(const std::string& folder) {
#ifdef O_TMPFILE
  const int fd = ::open(folder.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0600);
  if (fd >= 0) return fd;
#endif
  std::string path = folder + "/.aal-pyramid-XXXXXX";
  const int named = ::mkstemp(path.data());
  if (named < 0) throw std::runtime_error(systemError("cannot create it", folder));
  ::unlink(path.c_str());
  return named;
}

// Blocks of 2^shift along one base-level block row: the maxima of `spanY`
// rows of `width` texels.
void blockRowMax(const float* rows, int spanY, int width, int shift, float* max) {
  std::fill(max, max + blocks(width, shift), kNoHeight);
  for (int i = 0; i < spanY; ++i) {
    const float* z = rows + static_cast<size_t>(i) * width;
    for (int col = 0; col < width; ++col) {
      const int bx = col >> shift;
      max[bx] = std::max(max[bx], z[col]);
    }
  }
}

}  // namespace

HeightPyramid::HeightPyramid(int width, int height, int baseShift, const std::string& fileFolder)
    : width_(width), height_(height) {
  if (width < 1 || height < 1 || baseShift < 0 || baseShift > 30) {
    throw std::invalid_argument("height pyramid: bad size or base shift");
  }
  for (int shift = baseShift;; ++shift) {
    Level level;
    level.shift = shift;
    level.width = blocks(width, shift);
    level.height = blocks(height, shift);
    level.offset = floats_;
    floats_ += static_cast<size_t>(level.width) * level.height;
    levels_.push_back(level);
    if (level.width == 1 && level.height == 1) break;
  }
  filled_.assign(static_cast<size_t>(levels_.front().height), 0);
  if (fileFolder.empty()) {
    memory_.assign(floats_, kNoHeight);
    return;
  }
  fd_ = openUnnamedFile(fileFolder);
  if (::ftruncate(fd_, static_cast<off_t>(bytes())) != 0) {
    const std::string message = systemError("cannot size it", fileFolder);
    ::close(fd_);
    throw std::runtime_error(message);
  }
}

HeightPyramid::~HeightPyramid() {
  if (fd_ >= 0) ::close(fd_);
}

HeightPyramid::HeightPyramid(HeightPyramid&& other) noexcept
    : width_(other.width_),
      height_(other.height_),
      floats_(other.floats_),
      fd_(std::exchange(other.fd_, -1)),
      memory_(std::move(other.memory_)),
      rowsAdded_(other.rowsAdded_),
      filledBlockRows_(other.filledBlockRows_),
      filled_(std::move(other.filled_)),
      levels_(std::move(other.levels_)),
      rowMax_(std::move(other.rowMax_)) {}

HeightPyramid& HeightPyramid::operator=(HeightPyramid&& other) noexcept {
  if (this == &other) return *this;
  if (fd_ >= 0) ::close(fd_);
  width_ = other.width_;
  height_ = other.height_;
  floats_ = other.floats_;
  fd_ = std::exchange(other.fd_, -1);
  memory_ = std::move(other.memory_);
  rowsAdded_ = other.rowsAdded_;
  filledBlockRows_ = other.filledBlockRows_;
  filled_ = std::move(other.filled_);
  levels_ = std::move(other.levels_);
  rowMax_ = std::move(other.rowMax_);
  return *this;
}

namespace {

// Moves `count` floats between `values` and the file at float `offset`
// with pread or pwrite, through short transfers and EINTR. Returns the
// bytes left unmoved: 0, or with errno set (0 at the file's end).
template <class Transfer, class Bytes>
size_t transferFloats(Transfer transfer, int fd, Bytes bytes, size_t offset, size_t count) {
  size_t left = count * sizeof(float);
  off_t at = static_cast<off_t>(offset * sizeof(float));
  errno = 0;
  while (left > 0) {
    const ssize_t n = transfer(fd, bytes, left, at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    bytes += n;
    left -= static_cast<size_t>(n);
    at += n;
  }
  return left;
}

}  // namespace

void HeightPyramid::writeFloats(size_t offset, const float* values, size_t count) {
  if (fd_ < 0) {
    std::copy(values, values + count, memory_.begin() + static_cast<std::ptrdiff_t>(offset));
    return;
  }
  if (transferFloats(::pwrite, fd_, reinterpret_cast<const char*>(values), offset, count) > 0) {
    throw std::runtime_error("far-field pyramid file: cannot write " + std::to_string(bytes()) +
                             " bytes: " + std::strerror(errno != 0 ? errno : ENOSPC));
  }
}

void HeightPyramid::readFloats(size_t offset, float* values, size_t count) const {
  if (fd_ < 0) {
    const auto first = memory_.begin() + static_cast<std::ptrdiff_t>(offset);
    std::copy(first, first + static_cast<std::ptrdiff_t>(count), values);
    return;
  }
  if (transferFloats(::pread, fd_, reinterpret_cast<char*>(values), offset, count) > 0) {
    throw std::runtime_error(std::string("far-field pyramid file: cannot read it back: ") +
                             (errno != 0 ? std::strerror(errno) : "it is shorter than written"));
  }
}

void HeightPyramid::addRows(const float* rows, int count) {
  if (count < 0 || rowsAdded_ + count > height_) {
    throw std::invalid_argument("height pyramid: more rows than the DEM has");
  }
  if (rowsAdded_ == 0 && filledBlockRows_ > 0) {
    throw std::invalid_argument("height pyramid: rows in order after block rows");
  }
  const Level& base = levels_.front();
  if (rowMax_.empty()) rowMax_.assign(static_cast<size_t>(base.width), kNoHeight);
  for (int i = 0; i < count; ++i) {
    const int row = rowsAdded_ + i;
    const float* z = rows + static_cast<size_t>(i) * width_;
    for (int col = 0; col < width_; ++col) {
      float& max = rowMax_[static_cast<size_t>(col >> base.shift)];
      max = std::max(max, z[col]);
    }
    if (row + 1 == height_ || ((row + 1) & ((1 << base.shift) - 1)) == 0) {
      const int blockRow = row >> base.shift;
      markFilled(blockRow, 1);
      writeFloats(base.offset + static_cast<size_t>(blockRow) * base.width, rowMax_.data(),
                  rowMax_.size());
      std::fill(rowMax_.begin(), rowMax_.end(), kNoHeight);
    }
  }
  rowsAdded_ += count;
  if (complete()) buildCoarserLevels();
}

void HeightPyramid::addBlockRows(int firstRow, const float* rows, int count) {
  const Level& base = levels_.front();
  const int blockTexels = 1 << base.shift;
  if (rowsAdded_ != 0 || firstRow < 0 || count < 1 || firstRow + count > height_ ||
      firstRow % blockTexels != 0 || (count % blockTexels != 0 && firstRow + count != height_)) {
    throw std::invalid_argument("height pyramid: rows " + std::to_string(firstRow) + " + " +
                                std::to_string(count) + " are not whole block rows");
  }
  const int firstBlock = firstRow >> base.shift;
  const int blockRows = blocks(count, base.shift);
  markFilled(firstBlock, blockRows);
  // Each block row's maxima as addRows makes them, then written in one go.
  std::vector<float> max(static_cast<size_t>(blockRows) * base.width);
  tbb::parallel_for(tbb::blocked_range<int>(0, blockRows), [&](const tbb::blocked_range<int>& r) {
    for (int b = r.begin(); b < r.end(); ++b) {
      blockRowMax(rows + static_cast<size_t>(b) * blockTexels * width_,
                  blockSpan(firstBlock + b, base.shift, height_), width_, base.shift,
                  max.data() + static_cast<size_t>(b) * base.width);
    }
  });
  writeFloats(base.offset + static_cast<size_t>(firstBlock) * base.width, max.data(), max.size());
  if (complete()) buildCoarserLevels();
}

void HeightPyramid::setBaseBlockRows(int firstBlockRow, int count, const float* max) {
  if (rowsAdded_ != 0) throw std::invalid_argument("height pyramid: rows were added already");
  const Level& base = levels_.front();
  markFilled(firstBlockRow, count);
  writeFloats(base.offset + static_cast<size_t>(firstBlockRow) * base.width, max,
              static_cast<size_t>(count) * base.width);
  if (complete()) buildCoarserLevels();
}

void HeightPyramid::readBlocks(int shift, int bx, int by, int w, int h, float* out) const {
  if (shift < baseShift() || shift > coarsestShift()) {
    throw std::out_of_range("height pyramid: no level of blocks of 2^" + std::to_string(shift));
  }
  const Level& l = level(shift);
  if (bx < 0 || by < 0 || w < 0 || h < 0 || bx + w > l.width || by + h > l.height) {
    throw std::out_of_range("height pyramid: blocks outside the level");
  }
  if (w == l.width) {  // whole rows: one read
    readFloats(l.offset + static_cast<size_t>(by) * l.width, out, static_cast<size_t>(w) * h);
    return;
  }
  for (int y = 0; y < h; ++y) {
    readFloats(l.offset + static_cast<size_t>(by + y) * l.width + bx,
               out + static_cast<size_t>(y) * w, static_cast<size_t>(w));
  }
}

std::vector<float> HeightPyramid::levelMax(int shift) const {
  const Level& l = level(shift);
  std::vector<float> max(static_cast<size_t>(l.width) * l.height);
  readBlocks(shift, 0, 0, l.width, l.height, max.data());
  return max;
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

void HeightPyramid::buildCoarserLevels() {
  rowMax_ = {};
  filled_ = {};
  // Row by row, two rows of the finer level to one of the coarser: a few
  // rows resident whether the levels are in memory or in the file.
  std::vector<float> fine, coarse;
  for (size_t l = 1; l < levels_.size(); ++l) {
    const Level& f = levels_[l - 1];
    const Level& c = levels_[l];
    fine.resize(2 * static_cast<size_t>(f.width));
    coarse.resize(static_cast<size_t>(c.width));
    for (int by = 0; by < c.height; ++by) {
      const int rows = std::min(2, f.height - 2 * by);
      readBlocks(f.shift, 0, 2 * by, f.width, rows, fine.data());
      for (int bx = 0; bx < c.width; ++bx) {
        float max = kNoHeight;
        for (int fy = 0; fy < rows; ++fy) {
          for (int fx = 2 * bx; fx < std::min(2 * bx + 2, f.width); ++fx) {
            max = std::max(max, fine[static_cast<size_t>(fy) * f.width + fx]);
          }
        }
        coarse[static_cast<size_t>(bx)] = max;
      }
      writeFloats(c.offset + static_cast<size_t>(by) * c.width, coarse.data(), coarse.size());
    }
  }
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
