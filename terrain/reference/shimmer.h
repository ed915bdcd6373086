// Shimmer of an image sequence: how much a picture flickers from frame to
// frame in a slow camera move, measured as the mean absolute temporal second
// difference of linear luminance, |Y(t+1) - 2 Y(t) + Y(t-1)|, over the pixels
// counted in all three frames (docs/comparison.md, "Shimmer in motion").
// A still sequence reads 0, and so does one whose luminance changes linearly
// in time (a smooth image moving steadily changes nearly so); aliasing that
// lights and darkens a pixel from one frame to the next reads high.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace aal {

class ShimmerMeter {
 public:
  // Adds the next frame: linear RGB radiance, row-major, and the pixels that
  // count (1), e.g. the terrain away from its silhouette. Every frame has the
  // size of the first; throws std::invalid_argument when a size differs.
  void addFrame(const std::vector<glm::vec3>& radiance, const std::vector<uint8_t>& mask);

  int frames() const { return frames_; }
  // Pixel terms the mean is over: for each frame t with a frame before and
  // after it, the pixels counted in frames t - 1, t and t + 1.
  size_t terms() const { return terms_; }
  // Mean |Y(t+1) - 2 Y(t) + Y(t-1)| over the terms (the radiance's unit,
  // e.g. kcd/m²); 0 while there are none (fewer than three frames).
  double meanSecondDifference() const { return terms_ > 0 ? sum_ / double(terms_) : 0.0; }

 private:
  std::vector<float> before_, current_;  // luminance of frames t - 1 and t
  std::vector<uint8_t> beforeMask_, currentMask_;
  double sum_ = 0;
  size_t terms_ = 0;
  int frames_ = 0;
};

}  // namespace aal
