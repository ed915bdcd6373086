#include "aperture/terrain/io/albedo_image.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <system_error>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/io/image_files.h"
#include "aperture/terrain/io/input_file.h"
#include "aperture/terrain/io/memory_budget.h"

namespace aal {

namespace {
// IEC 61966-2-1 decoding.
float srgbToLinear(float v) {
  return v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
}
// What the header claims must fit in memory and, for PNG, in the file, before
// a pixel is decoded: the image is decoded into floats of the size the header
// says, and copied, so a small file claiming 20000 x 20000 pixels (a bomb
// of zeros, or a damaged header) would take 9.6 GB before the decoder knew
// better (docs/dem-input.md, "Every input is a file").
void checkDeclaredSize(const std::string& path, const ImageHeader& header) {
  const std::string subject = "albedo image " + path;
  if (header.width < 1 || header.height < 1 || header.channels < 1) {
    throw InputError(subject + " is empty");
  }
  const double samples = double(header.width) * double(header.height) * double(header.channels);
  if (header.format == "png") {
    // zlib's best ratio is 1032:1 (258-byte matches in 2 bits), as for the
    // DEM's PNGs (dem_source.cpp); each row has a filter byte.
    std::error_code error;
    const uintmax_t fileBytes = std::filesystem::file_size(path, error);
    const double declared =
        double(header.height) *
        (1.0 + std::ceil(double(header.width) * header.channels * header.bitsPerSample / 8.0));
    if (!error && declared > 1032.0 * double(fileBytes)) {
      throw InputError(subject + " is truncated or corrupt: its header declares " +
                       std::to_string(header.width) + " x " + std::to_string(header.height) +
                       " pixels, " + formatBytes(declared) + " of samples, but at zlib's best " +
                       "ratio (1032:1) its " + std::to_string(fileBytes) + " bytes hold at most " +
                       formatBytes(1032.0 * double(fileBytes)));
    }
  }
  // Decoded as floats by the image library, then copied: 8 bytes a sample.
  requireMemory(subject, 8.0 * samples,
                "its " + std::to_string(header.width) + " x " + std::to_string(header.height) +
                    " pixels of " + std::to_string(header.channels) + " channels as floats",
                "it is resampled to the DEM's size anyway: resize it first, e.g. `oiiotool " +
                    path + " --resize WxH -o smaller.png`");
}

}  // namespace

AlbedoImage loadAlbedoImage(const std::string& path, int width, int height,
                            const std::function<void(const std::string&)>& note) {
  // Looked at before it is opened: a FIFO would block the read forever.
  switch (requireFileOrFolder(path, "albedo image " + path)) {
    case InputKind::Missing: throw InputError("albedo image " + path + " does not exist");
    case InputKind::Folder:
      throw InputError("albedo image " + path + " is a folder, not an image file");
    default: break;
  }
  try {
    checkDeclaredSize(path, readImageHeader(path));
  } catch (const ImageFileError& e) {
    throw InputError("cannot read albedo image " + path + ": " + e.what());
  }
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
