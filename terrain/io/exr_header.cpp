#include "exr_header.h"

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>

#include "errors.h"
#include "raw_dem.h"

namespace aal {

namespace {

// OpenEXR file layout (openexr.com, "OpenEXR File Layout"): magic, a version
// word with flags, then attributes "name\0type\0" int32 size, value, ended
// by an empty name.
constexpr uint32_t kLongNames = 0x400, kNonImage = 0x800;

class HeaderReader {
 public:
  HeaderReader(const std::string& path, uintmax_t size)
      : path_(path), in_(path, std::ios::binary), size_(size) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(path_ + ": corrupt OpenEXR header: " + problem);
  }

  uint32_t u32() {
    unsigned char b[4];
    if (!in_.read(reinterpret_cast<char*>(b), 4)) fail("it ends early");
    return uint32_t{b[0]} | uint32_t{b[1]} << 8 | uint32_t{b[2]} << 16 | uint32_t{b[3]} << 24;
  }

  // A NUL-terminated string of at most maxLength characters.
  std::string text(size_t maxLength) {
    std::string s;
    char c = 0;
    while (in_.get(c) && c != '\0') {
      if (s.size() == maxLength)
        fail("a name longer than " + std::to_string(maxLength) + " characters");
      s += c;
    }
    if (!in_) fail("it ends early");
    return s;
  }

  void skip(uint32_t bytes) {
    const auto position = static_cast<uintmax_t>(in_.tellg());
    if (bytes > size_ - position)
      fail("an attribute of " + std::to_string(bytes) + " bytes runs past the end of the file");
    in_.seekg(static_cast<std::streamoff>(bytes), std::ios::cur);
  }

 private:
  std::string path_;
  std::ifstream in_;
  uintmax_t size_;
};

}  // namespace

void checkExrHeader(const std::string& path, const DemLoadOptions& options) {
  std::error_code error;
  const uintmax_t size = std::filesystem::file_size(path, error);
  if (error) throw InputError(path + ": cannot read: " + error.message());
  HeaderReader reader(path, size);
  if (reader.u32() != 20000630u) reader.fail("wrong magic number");
  const uint32_t version = reader.u32();
  if (version & kNonImage) throw InputError(path + ": deep (non-image) OpenEXR files are not DEMs");
  const size_t maxName = (version & kLongNames) ? 255 : 31;

  std::optional<std::pair<int64_t, int64_t>> dataWindow;
  for (;;) {
    const std::string name = reader.text(maxName);
    if (name.empty()) break;  // end of the (first) header
    const std::string type = reader.text(maxName);
    const uint32_t bytes = reader.u32();
    if (name == "dataWindow" && type == "box2i" && bytes == 16) {
      const auto xMin = static_cast<int32_t>(reader.u32()),
                 yMin = static_cast<int32_t>(reader.u32());
      const auto xMax = static_cast<int32_t>(reader.u32()),
                 yMax = static_cast<int32_t>(reader.u32());
      dataWindow = {int64_t{xMax} - xMin + 1, int64_t{yMax} - yMin + 1};
    } else {
      reader.skip(bytes);
    }
  }
  if (!dataWindow) reader.fail("no dataWindow");
  checkDemSize(path, dataWindow->first, dataWindow->second, options.maxTexels);
}

}  // namespace aal
