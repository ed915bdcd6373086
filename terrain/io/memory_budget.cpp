#include "aperture/terrain/io/memory_budget.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include <sys/resource.h>

#include "aperture/terrain/errors.h"

namespace aal {

namespace {

std::optional<uint64_t> limitFromEnvironment() {
  const char* text = std::getenv("AAL_MEMORY_LIMIT");
  if (text == nullptr || *text == '\0') return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text, &end);
  double unit = 1;
  if (*end == 'K' || *end == 'k')
    unit = 1024.0, ++end;
  else if (*end == 'M' || *end == 'm')
    unit = 1024.0 * 1024.0, ++end;
  else if (*end == 'G' || *end == 'g')
    unit = 1024.0 * 1024.0 * 1024.0, ++end;
  const double bytes = value * unit;
  if (errno != 0 || end == text || *end != '\0' || !(bytes >= 1.0 && bytes < 1.8e19)) {
    throw InputError(std::string("AAL_MEMORY_LIMIT must be a positive size in bytes (K, M or G "
                                 "may follow), got \"") +
                     text + "\"");
  }
  return static_cast<uint64_t>(bytes);
}

// A "Key:   N kB" line of a /proc file, in bytes.
std::optional<uint64_t> procKilobytes(const char* file, const std::string& wanted) {
  std::ifstream in(file);
  std::string key;
  uint64_t kilobytes = 0;
  while (in >> key) {
    if (key == wanted && in >> kilobytes) return kilobytes * 1024;
    in.ignore(4096, '\n');
  }
  return std::nullopt;
}

// What a resource limit leaves above what the process uses now.
std::optional<uint64_t> rlimitLeft(int resource, const std::string& usedKey) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return std::nullopt;
  const uint64_t used = procKilobytes("/proc/self/status", usedKey).value_or(0);
  return limit.rlim_cur > used ? limit.rlim_cur - used : 0;
}

std::optional<uint64_t> readNumber(const std::string& path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return std::nullopt;
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (end == text.c_str() || *end != '\0') return std::nullopt;
  return value;
}

// The cgroup v2 limit of this process ("0::/PATH" in /proc/self/cgroup).
std::optional<uint64_t> cgroupLeft() {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("0::", 0) != 0) continue;
    const std::string folder = "/sys/fs/cgroup" + line.substr(3);
    const std::optional<uint64_t> max = readNumber(folder + "/memory.max");
    if (!max) return std::nullopt;
    const uint64_t current = readNumber(folder + "/memory.current").value_or(0);
    return *max > current ? *max - current : 0;
  }
  return std::nullopt;
}

}  // namespace

std::optional<MemoryLimit> memoryLimit() {
  if (auto limit = limitFromEnvironment()) return MemoryLimit{*limit, "AAL_MEMORY_LIMIT"};
  std::optional<MemoryLimit> tightest;
  const auto consider = [&](std::optional<uint64_t> bytes, const char* source) {
    if (bytes && (!tightest || *bytes < tightest->bytes)) tightest = MemoryLimit{*bytes, source};
  };
  consider(procKilobytes("/proc/meminfo", "MemAvailable:"), "the system's available memory");
  consider(rlimitLeft(RLIMIT_AS, "VmSize:"), "ulimit -v");
  consider(rlimitLeft(RLIMIT_DATA, "VmData:"), "ulimit -d");
  consider(cgroupLeft(), "cgroup memory.max");
  return tightest;
}

std::optional<uint64_t> availableMemoryBytes() {
  const std::optional<MemoryLimit> limit = memoryLimit();
  return limit ? std::optional(limit->bytes) : std::nullopt;
}

std::string formatBytes(double bytes) {
  char text[32];
  if (bytes >= 1e9) {
    std::snprintf(text, sizeof text, "%.2f GB", bytes / 1e9);
  } else if (bytes >= 1e6) {
    std::snprintf(text, sizeof text, "%.1f MB", bytes / 1e6);
  } else {
    std::snprintf(text, sizeof text, "%.0f kB", bytes / 1e3);
  }
  return text;
}

void requireMemory(const std::string& path, double bytes, const std::string& what,
                   const std::string& hint) {
  const std::optional<MemoryLimit> limit = memoryLimit();
  if (!limit || bytes <= static_cast<double>(limit->bytes)) return;
  throw InputError(path + ": holding " + what + " needs " + formatBytes(bytes) + ", but only " +
                   formatBytes(static_cast<double>(limit->bytes)) + " of memory is available (" +
                   limit->source + "); " + hint);
}

std::string outOfMemoryMessage(const std::string& doing) {
  std::string message = "out of memory" + (doing.empty() ? "" : " while " + doing);
  std::optional<MemoryLimit> limit;
  try {
    limit = memoryLimit();
  } catch (const std::exception&) {
  }
  if (limit && limit->source != "the system's available memory") {
    message += " (" + limit->source + " leaves " + formatBytes(double(limit->bytes)) +
               "): raise the limit, or give the tool a smaller DEM or output";
  } else {
    message += ": free memory, or give the tool a smaller DEM or output";
  }
  return message;
}

}  // namespace aal
