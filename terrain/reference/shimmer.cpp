#include "aperture/terrain/reference/shimmer.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "aperture/terrain/light/atmosphere.h"

namespace aal {

void ShimmerMeter::addFrame(const std::vector<glm::vec3>& radiance,
                            const std::vector<uint8_t>& mask) {
  if (radiance.size() != mask.size() || (frames_ > 0 && radiance.size() != current_.size())) {
    throw std::invalid_argument("ShimmerMeter: every frame and its mask must have one size");
  }
  std::vector<float> next(radiance.size());
  for (size_t i = 0; i < radiance.size(); ++i) next[i] = luminance(radiance[i]);
  if (frames_ >= 2) {
    for (size_t i = 0; i < next.size(); ++i) {
      if (!mask[i] || !currentMask_[i] || !beforeMask_[i]) continue;
      sum_ += std::abs(double(next[i]) - 2.0 * double(current_[i]) + double(before_[i]));
      ++terms_;
    }
  }
  before_ = std::exchange(current_, std::move(next));
  beforeMask_ = std::exchange(currentMask_, mask);
  ++frames_;
}

}  // namespace aal
