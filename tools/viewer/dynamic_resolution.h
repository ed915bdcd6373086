// The viewer's dynamic resolution: while the view changes, the
// frame is drawn at a fraction of the window's pixels (scaled up; engine
// FrameOutput::resolutionScale) chosen to keep a target frame rate; as soon
// as it rests, a frame at full resolution. Pure policy, no window or device.
#pragma once

namespace aal {

class DynamicResolution {
 public:
  // The scale never drops below this (a quarter of the pixels) when the
  // smaller picture is scaled up, ...
  static constexpr float kMinimumScale = 0.5f;
  // ... nor below this (an eighth) when it is rebuilt from the frames
  // before (FrameOutput::temporal): there a third of the width is about as
  // close to the converged picture as a frame drawn at full resolution, and
  // closer to that frame than half the width scaled up (docs/viewer.md).
  static constexpr float kRebuiltMinimumScale = 0.35f;

  // `targetFps` <= 0 switches it off (always full resolution).
  explicit DynamicResolution(double targetFps = 0) { setTargetFps(targetFps); }
  void setTargetFps(double targetFps);
  double targetFps() const { return targetFps_; }
  // kMinimumScale or kRebuiltMinimumScale (frames rebuilt or not); a scale
  // below a raised floor rises to it.
  void setRebuilt(bool rebuilt);
  float minimumScale() const { return minimum_; }

  // The fraction of the width and height to draw the next frame at: 1 when
  // off or when the view rests (`moving` false).
  float scaleFor(bool moving) const;
  // After a frame drawn at scaleFor(moving): its wall time (ms). Frames over
  // the target lower the scale in proportion to the excess (pixels cost about
  // the square of the scale), frames well under it raise it gently, so the
  // scale settles instead of oscillating; resting frames change nothing.
  void frameFinished(double frameMs, bool moving);

 private:
  double targetFps_ = 0;
  float scale_ = 1.0f;  // while moving
  float minimum_ = kMinimumScale;
};

}  // namespace aal
