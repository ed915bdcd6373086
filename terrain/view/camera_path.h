// Camera paths for scripted viewer runs and demos (aal-view --camera-path):
// keyframes in a small text file, interpolated linearly.
//
// File format: one keyframe per line,
//   TIME_S  X Y Z  LOOK_X LOOK_Y LOOK_Z  [FOV_DEG]
// with the time in seconds (strictly increasing from line to line), the camera
// position and the point it looks at in metres in the DEM frame of
// docs/design.md §1 (as aal-render --camera/--look-at), and an optional
// vertical field of view in degrees (default 40, in [1, 170] as aal-render's
// --fov). Fields are separated by
// spaces or tabs; '#' starts a comment; blank lines are ignored. At least one
// keyframe.
#pragma once

#include <string>
#include <vector>

#include "aperture/terrain/view/camera.h"

namespace aal {

struct CameraKeyframe {
  double timeS = 0;
  Camera camera;
  int line = 0;  // in the file, for messages
};

class CameraPath {
 public:
  // Parses the text of a path file; `name` (the file) goes into messages.
  // Throws InputError naming the line for anything malformed: wrong field
  // count, non-numbers, non-finite values, times not increasing, a position
  // equal to its look-at point, a field of view outside [kMinFovDeg,
  // kMaxFovDeg] (--fov's range).
  static CameraPath parse(const std::string& text, const std::string& name);
  // Reads and parses a file (terrain/io/input_file.h, readTextInput: a
  // regular file of at most 16 MiB; a UTF-8 byte order mark at its start is
  // skipped); throws InputError naming the file when it is missing, a
  // folder, not a regular file, over the cap, or cannot be read or parsed.
  static CameraPath load(const std::string& path);

  const std::vector<CameraKeyframe>& keyframes() const { return keyframes_; }
  double startS() const { return keyframes_.front().timeS; }
  double endS() const { return keyframes_.back().timeS; }
  // The camera at `timeS`: linear between the two keyframes around it
  // (position, look-at and field of view), clamped to the first and last.
  Camera at(double timeS) const;
  // The time of frame `index` of `frameCount` spread evenly from the first
  // keyframe to the last (both included).
  double frameTime(int index, int frameCount) const;

 private:
  std::vector<CameraKeyframe> keyframes_;
};

}  // namespace aal
