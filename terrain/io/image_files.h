// Image files other than aperture maps: albedo images read, rendered frames
// and plots written. They go through OpenImageIO, which on Debian brings
// ~260 shared libraries (OpenCV, FFmpeg, GStreamer, ...) and costs every
// process that links it 0.3 s and 130 MB to start, so it lives in a plugin,
// aal_oiio_images.so next to the executables, opened by the first call here
// (docs/performance.md, "Start-up and image I/O"). AAL_IMAGE_PLUGIN names
// another file. A plugin that is missing or does not load is a
// std::runtime_error naming it and the loader's message.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace aal {

// What the image library said about a read, write, resize or text that
// failed; callers add which file and what for.
class ImageFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An image as floats, `channels` per pixel, rows top to bottom.
struct ImagePixels {
  int width = 0, height = 0, channels = 0;
  bool integerSamples = false;  // the file holds 8- or 16-bit integers, scaled to [0, 1] here
  std::vector<float> values;
};

// The first image in any file OpenImageIO reads (PNG, JPEG, TIFF, EXR, ...).
ImagePixels readImageFile(const std::string& path);

// What the header of an image file says, read without its pixels: so that
// a file whose header claims more than memory (or the file) holds is refused
// before it is decoded.
struct ImageHeader {
  int width = 0, height = 0, channels = 0;
  int bitsPerSample = 0;  // of the file's samples (8, 16, 32, ...)
  std::string format;     // OpenImageIO's name of the format: "png", "jpeg", "openexr", ...
};

// The header of the first image in the file (ImageFileError when
// OpenImageIO cannot read it).
ImageHeader readImageHeader(const std::string& path);

// `image` resampled to width x height with a triangle (bilinear) filter.
ImagePixels resizeImage(const ImagePixels& image, int width, int height);

// Writes `channels` samples per pixel, rows top to bottom, in the format the
// extension of `path` names: 8-bit samples as they are, floats as floats or,
// with `eightBit`, rounded to 8 bits.
void writeImageFile(const std::string& path, int width, int height, int channels,
                    const uint8_t* samples);
void writeImageFile(const std::string& path, int width, int height, int channels,
                    const float* samples, bool eightBit);

enum class TextAlign { Left, Center, Right };

// Draws `text` into an RGB float image (3 floats per pixel, rows top to
// bottom) with the TrueType font in `fontPath`, `size` pixels high, its
// baseline at y and its left end, centre or right end at x.
void drawText(float* rgb, int width, int height, int x, int y, const std::string& text, int size,
              const std::string& fontPath, const std::array<float, 3>& colour, TextAlign align);

}  // namespace aal
