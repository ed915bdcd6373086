#include "albedo_image.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>

#include "errors.h"

namespace aal {

namespace {
// IEC 61966-2-1 decoding.
float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}
}  // namespace

AlbedoImage loadAlbedoImage(const std::string& path, int width, int height,
                            const std::function<void(const std::string&)>& note) {
  if (!std::filesystem::exists(path)) throw InputError("albedo image " + path + " does not exist");
  OIIO::ImageBuf source(path);
  if (!source.read(0, 0, true, OIIO::TypeDesc::FLOAT)) {
    throw InputError("cannot read albedo image " + path + ": " + source.geterror());
  }
  const OIIO::ImageSpec& spec = source.spec();
  if (spec.width < 1 || spec.height < 1 || spec.nchannels < 1) {
    throw InputError("albedo image " + path + " is empty");
  }
  // The file's own sample type: spec() is the buffer's, float after read().
  const bool encoded = !source.nativespec().format.is_floating_point();
  OIIO::ImageBuf image = source;
  if (spec.width != width || spec.height != height) {
    if (note) {
      note("albedo image " + path + " is " + std::to_string(spec.width) + "x" +
           std::to_string(spec.height) + ", the DEM " + std::to_string(width) + "x" +
           std::to_string(height) + ": resampled to the DEM");
    }
    OIIO::ImageSpec target(width, height, spec.nchannels, OIIO::TypeDesc::FLOAT);
    image = OIIO::ImageBufAlgo::resize(source, "triangle", 0.0f,
                                       OIIO::ROI(0, width, 0, height, 0, 1, 0, spec.nchannels));
    if (image.has_error())
      throw InputError("cannot resample albedo image " + path + ": " + image.geterror());
  }
  AlbedoImage albedo;
  albedo.width = width;
  albedo.height = height;
  albedo.rgb.resize(static_cast<size_t>(width) * height * 3);
  std::vector<float> pixel(static_cast<size_t>(spec.nchannels));
  size_t i = 0;
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x, ++i) {
      image.getpixel(x, y, pixel.data(), spec.nchannels);
      for (int c = 0; c < 3; ++c) {
        float v = pixel[static_cast<size_t>(std::min(c, spec.nchannels < 3 ? 0 : c))];
        if (encoded) v = srgbToLinear(std::clamp(v, 0.0f, 1.0f));
        albedo.rgb[3 * i + c] = std::clamp(v, 0.0f, 1.0f);
      }
    }
  }
  return albedo;
}

}  // namespace aal
