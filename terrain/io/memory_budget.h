// How much memory a tool may take for one DEM-sized allocation, so that a
// huge raster (or a tiny file whose header claims one) is refused with the
// numbers before its samples are allocated, not after the system swaps.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace aal {

// Bytes the process may allocate now: AAL_MEMORY_LIMIT when set (bytes, or
// with a K, M, G suffix: a cap for shared machines, and how the tests pose
// a small one), else /proc/meminfo's MemAvailable. Nothing when unknown.
// Throws InputError when AAL_MEMORY_LIMIT is not a positive size.
std::optional<uint64_t> availableMemoryBytes();

// "1.23 GB": sizes in messages.
std::string formatBytes(double bytes);

// Throws InputError("PATH: holding WHAT needs N, only M is available ...")
// when `bytes` exceed availableMemoryBytes(); `what` names the data, `hint`
// ends the message with a way out.
void requireMemory(const std::string& path, double bytes, const std::string& what,
                   const std::string& hint);

}  // namespace aal
