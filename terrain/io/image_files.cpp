#include "aperture/terrain/io/image_files.h"

#include <dlfcn.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <vector>

#include "aperture/terrain/io/image_plugin.h"
#include "aperture/terrain/io/memory_budget.h"

namespace aal {

namespace {
constexpr uint64_t kPluginAddressSpaceBytes = uint64_t{512} << 20;
}  // namespace

std::vector<std::string> imagePluginCandidates() {
  std::vector<std::string> places;
  std::error_code error;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (!error) {
    const std::filesystem::path folder = executable.parent_path();
    places.push_back((folder / AAL_IMAGE_PLUGIN_FILE).string());
    places.push_back(
        (folder / AAL_IMAGE_PLUGIN_FROM_BIN / AAL_IMAGE_PLUGIN_FILE).lexically_normal().string());
  }
  places.push_back(AAL_IMAGE_PLUGIN_INSTALLED "/" AAL_IMAGE_PLUGIN_FILE);
  return places;
}

std::string imagePluginPath() {
  if (const char* path = std::getenv("AAL_IMAGE_PLUGIN"); path && *path) return path;
  const std::vector<std::string> places = imagePluginCandidates();
  for (const std::string& place : places) {
    std::error_code error;
    if (std::filesystem::is_regular_file(place, error)) return place;
  }
  return places.front();  // missing: the error names where a build puts it
}

const ImagePlugin& openImagePlugin(const std::string& path) {
  const std::string cannot = "cannot load the image plugin " + path + ": ";
  const std::string how = " (" AAL_IMAGE_PLUGIN_FILE
                          " is built next to the tools and installed in " AAL_IMAGE_PLUGIN_INSTALLED
                          "; AAL_IMAGE_PLUGIN names another path)";
  // dlerror() starts with the path: say it once.
  auto why = [&path] {
    const char* error = dlerror();
    std::string text = error ? error : "unknown error";
    if (text.rfind(path + ": ", 0) == 0) text.erase(0, path.size() + 2);
    return text;
  };
  // OpenImageIO and the ~260 libraries it links map 429 MiB (measured,
  // VmSize before and after dlopen); under a tighter ulimit -v a static
  // initialiser among them throws std::bad_alloc through dlopen, which ends
  // the process: refused before.
  if (const std::optional<std::string> shortfall =
          addressSpaceShortfall(kPluginAddressSpaceBytes, "loading it")) {
    throw std::runtime_error(cannot + *shortfall);
  }
  // Never closed: OpenImageIO keeps threads and caches until the process ends.
  void* library = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!library) {
    std::string reason = why();
    // OpenImageIO's ~260 libraries do not map under a tight ulimit -v.
    if (reason.find("failed to map") != std::string::npos ||
        reason.find("annot allocate memory") != std::string::npos) {
      reason += "; " + outOfMemoryMessage("loading it");
    }
    throw std::runtime_error(cannot + reason + how);
  }
  void* entry = dlsym(library, kImagePluginEntry);
  if (!entry) throw std::runtime_error(cannot + "not an image plugin: " + why());
  const ImagePlugin* plugin = reinterpret_cast<ImagePluginEntry>(entry)();
  if (!plugin || plugin->version != kImagePluginVersion) {
    throw std::runtime_error(cannot + "made for another version of aperture (table version " +
                             std::to_string(plugin ? plugin->version : 0) + ", expected " +
                             std::to_string(kImagePluginVersion) + ")" + how);
  }
  return *plugin;
}

namespace {

const ImagePlugin& plugin() {
  // Loaded on first use; a failed load throws and is tried again next time.
  static const ImagePlugin& loaded = openImagePlugin(imagePluginPath());
  return loaded;
}

void check(const std::string& error) {
  if (!error.empty()) throw ImageFileError(error);
}

}  // namespace

ImagePixels readImageFile(const std::string& path) {
  ImagePixels image;
  check(plugin().read(path, image));
  return image;
}

ImageHeader readImageHeader(const std::string& path) {
  ImageHeader header;
  check(plugin().readHeader(path, header));
  return header;
}

ImagePixels resizeImage(const ImagePixels& image, int width, int height) {
  ImagePixels resized;
  check(plugin().resize(image, width, height, resized));
  return resized;
}

void writeImageFile(const std::string& path, int width, int height, int channels,
                    const uint8_t* samples) {
  check(plugin().write(path, width, height, channels, samples, false, false));
}

void writeImageFile(const std::string& path, int width, int height, int channels,
                    const float* samples, bool eightBit) {
  check(plugin().write(path, width, height, channels, samples, true, !eightBit));
}

void drawText(float* rgb, int width, int height, int x, int y, const std::string& text, int size,
              const std::string& fontPath, const std::array<float, 3>& colour, TextAlign align) {
  check(plugin().drawText(rgb, width, height, x, y, text, size, fontPath, colour.data(), align));
}

}  // namespace aal
