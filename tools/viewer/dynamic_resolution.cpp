#include "aperture/tools/viewer/dynamic_resolution.h"

#include <algorithm>
#include <cmath>

namespace aal {

void DynamicResolution::setTargetFps(double targetFps) {
  targetFps_ = std::isfinite(targetFps) && targetFps > 0 ? targetFps : 0;
  if (targetFps_ == 0) scale_ = 1.0f;
}

void DynamicResolution::setRebuilt(bool rebuilt) {
  minimum_ = rebuilt ? kRebuiltMinimumScale : kMinimumScale;
  scale_ = std::max(scale_, minimum_);
}

float DynamicResolution::scaleFor(bool moving) const {
  return moving && targetFps_ > 0 ? scale_ : 1.0f;
}

void DynamicResolution::frameFinished(double frameMs, bool moving) {
  if (!moving || targetFps_ <= 0 || !(frameMs > 0)) return;
  const double targetMs = 1000.0 / targetFps_;
  double next = scale_;
  if (frameMs > 1.05 * targetMs) {
    // Part of a frame does not shrink with the pixels (presenting, the
    // geometry): move halfway to where the pixels alone would have to go.
    next = scale_ * (0.5 + 0.5 * std::sqrt(targetMs / frameMs));
  } else if (frameMs < 0.8 * targetMs) {
    next = scale_ * 1.05;
  }
  scale_ = static_cast<float>(std::clamp(next, double(minimum_), 1.0));
}

}  // namespace aal
