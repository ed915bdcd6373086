// Writing rendered frames: PNG (8-bit, display-encoded) or EXR (linear HDR),
// chosen by the file extension, via a temporary file renamed into place,
// through the image plugin (image_files.h).
#pragma once

#include <string>

namespace aal {

struct FrameResult;

// True for extensions the renderer can write: .png, .exr (case-insensitive).
bool isSupportedImageOutput(const std::string& path);
// True when `path` asks for linear HDR output (.exr).
bool wantsLinearOutput(const std::string& path);

// Writes `frame` to `path`: .png from frame.display, .exr from frame.linear
// (RGB, float). Throws std::runtime_error when the file cannot be written.
void writeFrame(const std::string& path, const FrameResult& frame);

}  // namespace aal
