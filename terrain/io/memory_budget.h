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
  // "AAL_MEMORY_LIMIT", "ulimit -v", "ulimit -d", "cgroup memory.max" (v2),
  // "cgroup memory.limit_in_bytes" (v1) or "the system's available memory"
  // (/proc/meminfo's MemAvailable).
  std::string source;
};

// What each tool holds at its peak per DEM texel, its DEM's heights and void
// mask included (DemLoadOptions::peakBytesPerTexel): the growth of the
// maximum resident set from a 2048² to a 4096² fBm DEM, rounded up
// (docs/performance.md, "Memory"). A GPU render on lavapipe keeps its
// textures in host memory, and bakes the aperture map first when none is
// cached (31.7 measured; 28.8 with the map cached).
constexpr double kRenderBytesPerTexel = 32;
constexpr double kReferenceRenderBytesPerTexel = 8;  // the ray tracer (6.6)
constexpr double kReliefBytesPerTexel = 28;          // aal-relief (27.4)

// AAL_MEMORY_LIMIT when set (bytes, or with a K, M, G suffix: a cap for
// shared machines, and how the tests pose a small one); else the least of
// /proc/meminfo's MemAvailable, what the address-space and data limits
// (ulimit -v, ulimit -d) leave above what the process maps now, and what
// the cgroups of the process and their ancestors leave above their use (v2's
// memory.max over memory.current, v1's memory.limit_in_bytes over
// memory.usage_in_bytes: how Slurm and containers limit a job; the
// hierarchies under /sys/fs/cgroup, or under AAL_CGROUP_ROOT when set).
// Nothing when none is known. Throws InputError when AAL_MEMORY_LIMIT is not
// a positive size.
std::optional<MemoryLimit> memoryLimit();

// What ulimit -v (RLIMIT_AS) leaves above the address space the process
// maps now; nothing when it is unlimited.
std::optional<uint64_t> addressSpaceLeft();

// "WHAT needs about N MiB of address space, and this process's limit
// (ulimit -v K kB) leaves M MiB: raise or remove the limit" when ulimit -v
// leaves less than `bytes`; nothing otherwise. For what maps far more than
// it allocates (a Vulkan driver, OpenImageIO's libraries) and aborts or
// throws from static initialisers when the mapping fails.
std::optional<std::string> addressSpaceShortfall(uint64_t bytes, const std::string& what);

// How many of `wanted` threads a pool may start: every thread's stack
// (RLIMIT_STACK's size, 8 MiB when that is unlimited) takes address space,
// so under ulimit -v only as many as fit in half of what is left beyond
// 64 MiB, and at least 1 (the caller's own). `wanted` without a limit.
unsigned threadsThatFit(unsigned wanted);

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
