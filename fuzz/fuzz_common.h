// Shared pieces of the libFuzzer targets: a per-process scratch file (the
// GeoTIFF, PNG and EXR readers need a path) and options that keep hostile
// headers from asking for gigabytes.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

#include "dem_options.h"

namespace aal::fuzz {

// 2^20 texels: big enough for any seed, small enough for libFuzzer's limits.
constexpr size_t kFuzzMaxTexels = size_t{1} << 20;

inline DemLoadOptions options() {
  DemLoadOptions o;
  o.warn = nullptr;  // warnings are expected; only crashes matter
  o.maxTexels = kFuzzMaxTexels;
  return o;
}

// The scratch folder of this process, removed when the process exits.
class ScratchFolder {
 public:
  ScratchFolder() {
    std::error_code error;
    const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", error)
                                           ? std::filesystem::path("/dev/shm")
                                           : std::filesystem::temp_directory_path();
    path_ = base / ("aal-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path_, error);
  }
  ~ScratchFolder() {
    std::error_code error;
    std::filesystem::remove_all(path_, error);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// PATH/NAME in a folder owned by this process, so that the file name itself
// (an SRTM tile name) is free.
inline std::string scratchPath(const std::string& name) {
  static const ScratchFolder folder;
  return (folder.path() / name).string();
}

inline void writeScratch(const std::string& path, const uint8_t* data, size_t size) {
  FILE* file = std::fopen(path.c_str(), "wb");
  if (!file) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
}

}  // namespace aal::fuzz
