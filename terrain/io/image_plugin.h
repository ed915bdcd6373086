// The table of functions the image plugin (aal_oiio_images.so, built from
// oiio_image_plugin.cpp) gives image_files.cpp. The plugin exports one C
// function, kImagePluginEntry, that returns it; `version` comes first and
// changes with the table, so that a plugin of another build is refused
// rather than called.
#pragma once

#include <string>
#include <vector>

#include "aperture/terrain/io/image_files.h"

namespace aal {

constexpr int kImagePluginVersion = 2;
constexpr const char* kImagePluginEntry = "aal_image_plugin";

struct ImagePlugin {
  int version = kImagePluginVersion;
  // Each returns "" when it succeeded, else the image library's message;
  // none throws.
  std::string (*read)(const std::string& path, ImagePixels& image);
  std::string (*resize)(const ImagePixels& image, int width, int height, ImagePixels& resized);
  // `samples` are bytes or floats (floatSamples); the file stores bytes or
  // floats (floatFile).
  std::string (*write)(const std::string& path, int width, int height, int channels,
                       const void* samples, bool floatSamples, bool floatFile);
  std::string (*drawText)(float* rgb, int width, int height, int x, int y, const std::string& text,
                          int size, const std::string& fontPath, const float* colour,
                          TextAlign align);
  // The header alone (since version 2).
  std::string (*readHeader)(const std::string& path, ImageHeader& header);
};

using ImagePluginEntry = const ImagePlugin* (*)();

// Opens the plugin at `path` (each call dlopens it again; image_files.cpp
// keeps the first). Throws std::runtime_error naming the file and saying
// why when it cannot be loaded, lacks the entry or is of another version.
const ImagePlugin& openImagePlugin(const std::string& path);

// Where image_files.cpp looks when AAL_IMAGE_PLUGIN is not set, in order:
// aal_oiio_images.so in the running executable's folder (the build tree),
// in <libdir>/aperture relative to it (installed tools, any prefix), and in
// the configured install prefix's <libdir>/aperture (programs that link the
// installed library).
std::vector<std::string> imagePluginCandidates();

// $AAL_IMAGE_PLUGIN, else the first of imagePluginCandidates() that exists,
// else the first of them (so that the error names where a build puts it).
std::string imagePluginPath();

}  // namespace aal
