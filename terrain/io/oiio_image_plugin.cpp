// The image plugin (aal_oiio_images.so): image_files.h's reads, writes,
// resizing and text through OpenImageIO, in a module of its own so that only
// the processes that touch such files load OpenImageIO and its ~260
// libraries (docs/performance.md, "Start-up and image I/O").
#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "aperture/terrain/io/image_plugin.h"

namespace aal {
namespace {

// Nothing may throw across the plugin's boundary.
template <typename Work>
std::string guarded(Work&& work) {
  try {
    return work();
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
    return "unknown error in the image plugin";
  }
}

std::string read(const std::string& path, ImagePixels& image) {
  return guarded([&]() -> std::string {
    OIIO::ImageBuf source(path);
    if (!source.read(0, 0, true, OIIO::TypeDesc::FLOAT)) return source.geterror();
    const OIIO::ImageSpec& spec = source.spec();
    image.width = spec.width;
    image.height = spec.height;
    image.channels = spec.nchannels;
    // The file's own sample type: spec() is the buffer's, float after read().
    image.integerSamples = !source.nativespec().format.is_floating_point();
    image.values.resize(spec.image_pixels() * static_cast<size_t>(spec.nchannels));
    if (!source.get_pixels(source.roi(), OIIO::TypeDesc::FLOAT, image.values.data())) {
      return source.geterror();
    }
    return "";
  });
}

std::string readHeader(const std::string& path, ImageHeader& header) {
  return guarded([&]() -> std::string {
    // open() reads the header (for PNG, the chunks before the pixels) only.
    auto input = OIIO::ImageInput::open(path);
    if (!input) return OIIO::geterror();
    const OIIO::ImageSpec& spec = input->spec();
    header.width = spec.width;
    header.height = spec.height;
    header.channels = spec.nchannels;
    header.bitsPerSample = static_cast<int>(8 * spec.format.size());
    if (const int bits = spec.get_int_attribute("oiio:BitsPerSample", 0); bits > 0) {
      header.bitsPerSample = bits;
    }
    header.format = input->format_name();
    input->close();
    return "";
  });
}

// An ImageBuf over the caller's floats (no copy).
OIIO::ImageBuf wrap(float* values, int width, int height, int channels) {
  return OIIO::ImageBuf(OIIO::ImageSpec(width, height, channels, OIIO::TypeDesc::FLOAT), values);
}

std::string resize(const ImagePixels& image, int width, int height, ImagePixels& resized) {
  return guarded([&]() -> std::string {
    // resize() only reads its source.
    const OIIO::ImageBuf source =
        wrap(const_cast<float*>(image.values.data()), image.width, image.height, image.channels);
    const OIIO::ImageBuf result = OIIO::ImageBufAlgo::resize(
        source, "triangle", 0.0f, OIIO::ROI(0, width, 0, height, 0, 1, 0, image.channels));
    if (result.has_error()) return result.geterror();
    resized.width = width;
    resized.height = height;
    resized.channels = image.channels;
    resized.integerSamples = image.integerSamples;
    resized.values.resize(static_cast<size_t>(width) * height * image.channels);
    if (!result.get_pixels(result.roi(), OIIO::TypeDesc::FLOAT, resized.values.data())) {
      return result.geterror();
    }
    return "";
  });
}

// Writes `bytes` to `path`, every error reported: OpenImageIO's PNG writer
// ignores a failed fwrite, and a full disk left a truncated PNG with exit 0.
std::string writeAll(const std::string& path, const std::vector<unsigned char>& bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return std::strerror(errno);
  size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int error = n < 0 ? errno : EIO;
      ::close(fd);
      return std::strerror(error);
    }
    done += static_cast<size_t>(n);
  }
  if (::close(fd) != 0) return std::strerror(errno);
  return "";
}

std::string write(const std::string& path, int width, int height, int channels, const void* samples,
                  bool floatSamples, bool floatFile) {
  return guarded([&]() -> std::string {
    auto out = OIIO::ImageOutput::create(path);
    if (!out) return OIIO::geterror();
    OIIO::ImageSpec spec(width, height, channels,
                         floatFile ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8);
    // 8-bit samples' colour is not multiplied by their alpha (as PNG stores
    // it): without this the writer would divide it by alpha once more.
    if (!floatFile) spec.attribute("oiio:UnassociatedAlpha", 1);
    // Encoded in memory, then written with checked system calls.
    std::vector<unsigned char> bytes;
    OIIO::Filesystem::IOVecOutput proxy(bytes);
    const bool inMemory = out->supports("ioproxy") && out->set_ioproxy(&proxy);
    if (!out->open(path, spec)) return out->geterror();
    if (!out->write_image(floatSamples ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8, samples) ||
        !out->close()) {
      return out->geterror();
    }
    return inMemory ? writeAll(path, bytes) : "";
  });
}

std::string drawText(float* rgb, int width, int height, int x, int y, const std::string& text,
                     int size, const std::string& fontPath, const float* colour, TextAlign align) {
  return guarded([&]() -> std::string {
    OIIO::ImageBuf image = wrap(rgb, width, height, 3);
    const auto alignX = align == TextAlign::Center  ? OIIO::ImageBufAlgo::TextAlignX::Center
                        : align == TextAlign::Right ? OIIO::ImageBufAlgo::TextAlignX::Right
                                                    : OIIO::ImageBufAlgo::TextAlignX::Left;
    if (!OIIO::ImageBufAlgo::render_text(image, x, y, text, size, fontPath,
                                         OIIO::cspan<float>(colour, 3), alignX)) {
      return image.geterror();
    }
    return "";
  });
}

const ImagePlugin kPlugin{kImagePluginVersion, read, resize, write, drawText, readHeader};

}  // namespace
}  // namespace aal

extern "C" __attribute__((visibility("default"))) const aal::ImagePlugin* aal_image_plugin() {
  return &aal::kPlugin;
}
