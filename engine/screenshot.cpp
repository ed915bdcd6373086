#include "aperture/engine/screenshot.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include "aperture/engine/terrain_renderer.h"
#include "aperture/terrain/io/atomic_file.h"
#include "aperture/terrain/io/image_files.h"

namespace aal {

namespace {
std::string extensionOf(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}
}  // namespace

bool isSupportedImageOutput(const std::string& path) {
  const std::string ext = extensionOf(path);
  return ext == ".png" || ext == ".exr";
}

bool wantsLinearOutput(const std::string& path) {
  return extensionOf(path) == ".exr";
}

void writeFrame(const std::string& path, const FrameResult& frame) {
  AtomicOutput output(path);
  const std::string temporary = output.temporaryPath().string();
  const int width = static_cast<int>(frame.width), height = static_cast<int>(frame.height);
  try {
    if (wantsLinearOutput(path)) {
      writeImageFile(temporary, width, height, 4, frame.linear.data(), /*eightBit=*/false);
    } else {
      writeImageFile(temporary, width, height, 4, frame.display.data());
    }
  } catch (const ImageFileError& e) {
    throw output.failure(e.what());
  }
  output.commit();
}

}  // namespace aal
