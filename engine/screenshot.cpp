#include "screenshot.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <stdexcept>

#include <OpenImageIO/imageio.h>

#include "atomic_file.h"
#include "terrain_renderer.h"

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
  auto out = OIIO::ImageOutput::create(temporary);
  if (!out) throw std::runtime_error("cannot write " + path + ": " + OIIO::geterror());
  const bool linear = wantsLinearOutput(path);
  OIIO::ImageSpec spec(static_cast<int>(frame.width), static_cast<int>(frame.height), 4,
                       linear ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
  if (!out->open(temporary, spec))
    throw std::runtime_error("cannot write " + path + ": " + out->geterror());
  const bool ok = linear ? out->write_image(OIIO::TypeDesc::FLOAT, frame.linear.data())
                         : out->write_image(OIIO::TypeDesc::UINT8, frame.display.data());
  if (!ok || !out->close())
    throw std::runtime_error("cannot write " + path + ": " + out->geterror());
  output.commit();
}

}  // namespace aal
