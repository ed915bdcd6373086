#include "aperture/terrain/io/memory_budget.h"

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>

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

}  // namespace

std::optional<uint64_t> availableMemoryBytes() {
  if (auto limit = limitFromEnvironment()) return limit;
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kilobytes = 0;
  while (meminfo >> key >> kilobytes) {
    if (key == "MemAvailable:") return kilobytes * 1024;
    meminfo.ignore(256, '\n');
  }
  return std::nullopt;
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
  const std::optional<uint64_t> available = availableMemoryBytes();
  if (!available || bytes <= static_cast<double>(*available)) return;
  throw InputError(path + ": holding " + what + " needs " + formatBytes(bytes) + ", but only " +
                   formatBytes(static_cast<double>(*available)) + " of memory is available" +
                   (std::getenv("AAL_MEMORY_LIMIT") ? " (AAL_MEMORY_LIMIT)" : "") + "; " + hint);
}

}  // namespace aal
