// The camera on a tool's command line: --camera, --look-at and --fov
// (aal-render), and --camera-path (aal-render, aal-view), whose file format
// both read alike (terrain/view/camera_path.h).
#pragma once

#include <string>

#include <CLI/CLI.hpp>

namespace aal {

struct CameraOptions {
  std::string position, lookAt;  // "X,Y,Z" in metres; empty: the default camera's
  double fovDeg = 40;            // vertical, degrees
};

// --camera, --look-at, --fov.
void addCameraOptions(CLI::App& app, CameraOptions& camera);

// --camera-path into `path`: the file's format, then `use`, what the tool
// does with it (aal-render renders a sequence along it, aal-view flies it).
void addCameraPathOption(CLI::App& app, std::string& path, const std::string& use);

}  // namespace aal
