// Damaging aperture map files on purpose, for the tests of their checks.
#pragma once

#include <OpenImageIO/imageio.h>

#include <fstream>
#include <ios>
#include <stdexcept>
#include <string>
#include <vector>

namespace aal::test {

// Flips the lowest bit of the byte `fromEnd` bytes before the end of `path`.
inline void flipByteFromEnd(const std::string& path, std::streamoff fromEnd) {
  std::fstream file(path, std::ios::binary | std::ios::in | std::ios::out);
  file.seekg(-fromEnd, std::ios::end);
  const char byte = static_cast<char>(file.get() ^ 1);
  file.seekp(-fromEnd, std::ios::end);
  file.put(byte);
  if (!file) throw std::runtime_error("cannot change " + path);
}

// Rewrites the map at `path` without its aal:pixelChecksum, as maps were
// written before it existed (the pixels and every other attribute kept).
inline void removePixelChecksum(const std::string& path) {
  OIIO::ImageSpec spec;
  std::vector<unsigned char> pixels;
  {
    auto in = OIIO::ImageInput::open(path);
    if (!in) throw std::runtime_error("cannot open " + path);
    spec = in->spec();
    pixels.resize(spec.image_bytes());
    if (!in->read_image(0, 0, 0, 4, spec.format, pixels.data())) {
      throw std::runtime_error("cannot read " + path);
    }
  }
  spec.erase_attribute("aal:pixelChecksum");
  auto out = OIIO::ImageOutput::create(path);
  if (!out || !out->open(path, spec) || !out->write_image(spec.format, pixels.data()) ||
      !out->close()) {
    throw std::runtime_error("cannot write " + path);
  }
}

}  // namespace aal::test
