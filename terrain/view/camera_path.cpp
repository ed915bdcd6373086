#include "aperture/terrain/view/camera_path.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/input_file.h"

namespace aal {

namespace {

CameraKeyframe parseLine(const std::string& line, const std::string& where) {
  std::istringstream in(line);
  std::vector<double> values;
  std::string token;
  while (in >> token) {
    size_t used = 0;
    double v = 0;
    try {
      v = std::stod(token, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used != token.size() || !std::isfinite(v)) {
      throw InputError(where + ": '" + token + "' is not a finite number");
    }
    values.push_back(v);
  }
  if (values.size() != 7 && values.size() != 8) {
    throw InputError(where + ": expected TIME_S X Y Z LOOK_X LOOK_Y LOOK_Z [FOV_DEG], got " +
                     std::to_string(values.size()) + " numbers");
  }
  CameraKeyframe key;
  key.timeS = values[0];
  key.camera.position = {values[1], values[2], values[3]};
  key.camera.lookAt = {values[4], values[5], values[6]};
  key.camera.verticalFovDeg = values.size() == 8 ? values[7] : 40.0;
  if (glm::length(key.camera.lookAt - key.camera.position) < 1e-6) {
    throw InputError(where + ": the camera position equals its look-at point");
  }
  if (!(key.camera.verticalFovDeg >= kMinFovDeg && key.camera.verticalFovDeg <= kMaxFovDeg)) {
    std::ostringstream fov;
    fov << key.camera.verticalFovDeg;
    throw InputError(where + ": field of view " + fov.str() + " degrees is outside [" +
                     std::to_string(int(kMinFovDeg)) + ", " + std::to_string(int(kMaxFovDeg)) +
                     "] (the range of --fov); give one in that range, or none for 40");
  }
  return key;
}

}  // namespace

CameraPath CameraPath::parse(const std::string& text, const std::string& name) {
  CameraPath path;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    line = line.substr(0, line.find('#'));
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::string where = "camera path " + name + " line " + std::to_string(number);
    CameraKeyframe key = parseLine(line, where);
    key.line = number;
    if (!path.keyframes_.empty() && !(key.timeS > path.keyframes_.back().timeS)) {
      throw InputError(where + ": times must increase from line to line");
    }
    path.keyframes_.push_back(key);
  }
  if (path.keyframes_.empty()) {
    throw InputError("camera path " + name +
                     " has no keyframes (TIME_S X Y Z LOOK_X LOOK_Y LOOK_Z)");
  }
  return path;
}

CameraPath CameraPath::load(const std::string& path) {
  // Capped, and only a regular file: a device or a FIFO would read forever.
  return parse(readTextInput(path, "camera path"), path);
}

Camera CameraPath::at(double timeS) const {
  if (timeS <= startS()) return keyframes_.front().camera;
  if (timeS >= endS()) return keyframes_.back().camera;
  const auto next =
      std::upper_bound(keyframes_.begin(), keyframes_.end(), timeS,
                       [](double t, const CameraKeyframe& key) { return t < key.timeS; });
  const CameraKeyframe& b = *next;
  const CameraKeyframe& a = *(next - 1);
  const double w = (timeS - a.timeS) / (b.timeS - a.timeS);
  Camera c;
  c.position = glm::mix(a.camera.position, b.camera.position, w);
  c.lookAt = glm::mix(a.camera.lookAt, b.camera.lookAt, w);
  c.verticalFovDeg =
      a.camera.verticalFovDeg + w * (b.camera.verticalFovDeg - a.camera.verticalFovDeg);
  // Interpolating both ends can make them meet: keep the earlier view then.
  if (glm::length(c.lookAt - c.position) < 1e-6)
    c.lookAt = c.position + (a.camera.lookAt - a.camera.position);
  return c;
}

double CameraPath::frameTime(int index, int frameCount) const {
  if (frameCount <= 1) return startS();
  return startS() + (endS() - startS()) * index / (frameCount - 1);
}

}  // namespace aal
