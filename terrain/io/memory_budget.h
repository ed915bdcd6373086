// How much memory a tool may take for one DEM-sized allocation, so that a
// huge raster (or a tiny file whose header claims one) is refused with the
// numbers before its samples are allocated, not after the system swaps or
// the allocator fails; and what to say when an allocation fails anyway.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace aal {

// The tightest limit on what the process may still allocate, and its name.
struct MemoryLimit {
  uint64_t bytes = 0;
  // "AAL_MEMORY_LIMIT", "ulimit -v", "ulimit -d", "cgroup memory.max" or
  // "the system's available memory" (/proc/meminfo's MemAvailable).
  std::string source;
};

// AAL_MEMORY_LIMIT when set (bytes, or with a K, M, G suffix: a cap for
// shared machines, and how the tests pose a small one); else the least of
// /proc/meminfo's MemAvailable, what the address-space and data limits
// (ulimit -v, ulimit -d) leave above what the process maps now, and what
// the cgroup v2 memory.max leaves above memory.current (how Slurm and
// containers limit a job). Nothing when none is known. Throws InputError
// when AAL_MEMORY_LIMIT is not a positive size.
std::optional<MemoryLimit> memoryLimit();

// memoryLimit()'s bytes.
std::optional<uint64_t> availableMemoryBytes();

// "1.23 GB": sizes in messages.
std::string formatBytes(double bytes);

// Throws InputError("PATH: holding WHAT needs N, only M is available (LIMIT)
// ...") when `bytes` exceed availableMemoryBytes(); `what` names the data,
// `hint` ends the message with a way out.
void requireMemory(const std::string& path, double bytes, const std::string& what,
                   const std::string& hint);

// "out of memory while DOING (ulimit -v leaves 1.00 GB): raise the limit,
// ...": the message for a failed allocation (std::bad_alloc, a library's),
// naming the limit that applies and what to do; `doing` may be empty.
std::string outOfMemoryMessage(const std::string& doing);

}  // namespace aal
