#include "aperture/terrain/io/albedo_image.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/image_files.h"

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
  ImagePixels image;
  try {
    image = readImageFile(path);
  } catch (const ImageFileError& e) {
    throw InputError("cannot read albedo image " + path + ": " + e.what());
  }
  if (image.width < 1 || image.height < 1 || image.channels < 1) {
    throw InputError("albedo image " + path + " is empty");
  }
  const int channels = image.channels;
  const bool encoded = image.integerSamples;
  if (image.width != width || image.height != height) {
    if (note) {
      note("albedo image " + path + " is " + std::to_string(image.width) + "x" +
           std::to_string(image.height) + ", the DEM " + std::to_string(width) + "x" +
           std::to_string(height) + ": resampled to the DEM");
    }
    try {
      image = resizeImage(image, width, height);
    } catch (const ImageFileError& e) {
      throw InputError("cannot resample albedo image " + path + ": " + e.what());
    }
  }
  AlbedoImage albedo;
  albedo.width = width;
  albedo.height = height;
  albedo.rgb.resize(static_cast<size_t>(width) * height * 3);
  for (size_t i = 0; i < albedo.rgb.size() / 3; ++i) {
    const float* pixel = image.values.data() + i * static_cast<size_t>(channels);
    for (int c = 0; c < 3; ++c) {
      float v = pixel[channels < 3 ? 0 : c];
      if (encoded) v = srgbToLinear(std::clamp(v, 0.0f, 1.0f));
      albedo.rgb[3 * i + c] = std::clamp(v, 0.0f, 1.0f);
    }
  }
  return albedo;
}

}  // namespace aal
