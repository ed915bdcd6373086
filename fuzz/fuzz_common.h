// Shared pieces of the libFuzzer targets: inputs become GDAL in-memory files
// (/vsimem/), options keep hostile headers from asking for gigabytes, and
// only the drivers of the formats we ship seeds for are registered, so that
// the fuzzers test our side of the GDAL boundary (terrain/io/dem_source.h),
// not Debian's build of every GDAL driver.
#pragma once

#include <cstddef>
#include <cstdint>
#include <set>
#include <string>

#include <cpl_vsi.h>
#include <gdal_priv.h>

#include "aperture/terrain/io/dem_options.h"
#include "aperture/terrain/io/gdal_session.h"

namespace aal::fuzz {

// 2^20 texels: big enough for any seed, small enough for libFuzzer's limits.
constexpr size_t kFuzzMaxTexels = size_t{1} << 20;

inline DemLoadOptions options() {
  DemLoadOptions o;
  o.warn = nullptr;  // warnings are expected; only crashes matter
  o.maxTexels = kFuzzMaxTexels;
  o.inMemoryFiles = true;  // the inputs are /vsimem/ files
  return o;
}

// GDAL with the GTiff, PNG, AAIGrid, SRTMHGT and MEM drivers only (VRT
// would let an input name any file on the machine).
inline void initGdal() {
  static const bool done = [] {
    ensureGdal();
    const std::set<std::string> keep = {"GTiff", "PNG", "AAIGrid", "SRTMHGT", "MEM"};
    GDALDriverManager* manager = GetGDALDriverManager();
    for (int i = manager->GetDriverCount() - 1; i >= 0; --i) {
      GDALDriver* driver = manager->GetDriver(i);
      if (keep.count(driver->GetDescription()) == 0) {
        manager->DeregisterDriver(driver);
        delete driver;
      }
    }
    return true;
  }();
  (void)done;
}

// The input as /vsimem/NAME for the lifetime of this object (not copied).
class MemoryFile {
 public:
  MemoryFile(const std::string& name, const uint8_t* data, size_t size) : path_("/vsimem/" + name) {
    VSIFCloseL(VSIFileFromMemBuffer(path_.c_str(), const_cast<GByte*>(data),
                                    static_cast<vsi_l_offset>(size), FALSE));
  }
  ~MemoryFile() { VSIUnlink(path_.c_str()); }
  MemoryFile(const MemoryFile&) = delete;
  MemoryFile& operator=(const MemoryFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace aal::fuzz
