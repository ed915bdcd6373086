// Large buffers (bake sums, DEMs read by GDAL) backed by 2 MiB pages where the kernel offers them
// (Linux transparent huge pages in "madvise" mode, Debian's default): one
// page fault per 2 MiB instead of per 4 KiB when the buffer is first
// written, and fewer TLB misses while the sweeps stride across it. The
// pages are also made (and zeroed by the kernel) on all threads before the
// buffer is filled: on a virtual machine that backs memory on first touch
// that was most of the set-up of a big bake, on one thread.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <tbb/parallel_for.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace aal {

// Advises the whole 2 MiB pages inside [data, data + bytes); a hint only.
inline void adviseHugePages(void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr uintptr_t kHuge = uintptr_t{2} << 20;
  const uintptr_t begin = (reinterpret_cast<uintptr_t>(data) + kHuge - 1) & ~(kHuge - 1);
  const uintptr_t end = (reinterpret_cast<uintptr_t>(data) + bytes) & ~(kHuge - 1);
  if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

// Makes the pages of [data, data + bytes) now, chunk by chunk on all
// threads (MADV_POPULATE_WRITE, Linux 5.14+; elsewhere the first writes
// make them). Nothing is read or written through the pointer.
inline void populatePages(void* data, size_t bytes) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr uintptr_t kChunk = uintptr_t{32} << 20;
  const uintptr_t begin = reinterpret_cast<uintptr_t>(data) & ~uintptr_t{4095};
  const uintptr_t end = reinterpret_cast<uintptr_t>(data) + bytes;
  if (end - begin < 2 * kChunk) return;  // not worth the threads
  tbb::parallel_for(begin, end, kChunk, [&](uintptr_t chunk) {
    madvise(reinterpret_cast<void*>(chunk), std::min(kChunk, end - chunk), MADV_POPULATE_WRITE);
  });
#else
  (void)data;
  (void)bytes;
#endif
}

// v.assign(n, value), with the storage advised and its pages made before
// it is first touched.
template <class T>
void assignOnHugePages(std::vector<T>& v, size_t n, const T& value) {
  v.clear();
  v.reserve(n);
  adviseHugePages(v.data(), n * sizeof(T));
  populatePages(v.data(), n * sizeof(T));
  v.assign(n, value);
}

}  // namespace aal
