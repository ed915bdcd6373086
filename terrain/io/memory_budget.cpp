#include "aperture/terrain/io/memory_budget.h"

#include <algorithm>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <vector>

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

// The folder of the cgroup hierarchies: /sys/fs/cgroup, or AAL_CGROUP_ROOT
// (how the tests pose a limit without one).
std::string cgroupRoot() {
  const char* root = std::getenv("AAL_CGROUP_ROOT");
  return root != nullptr && *root != '\0' ? root : "/sys/fs/cgroup";
}

// "/a/b" and its ancestors "/a" and "/", leaf first.
std::vector<std::string> selfAndAncestors(std::string path) {
  std::vector<std::string> folders;
  while (!path.empty() && path != "/") {
    folders.push_back(path);
    const size_t slash = path.find_last_of('/');
    if (slash == std::string::npos) break;
    path.erase(slash);
  }
  folders.push_back("");
  return folders;
}

// What the cgroups of this process leave above their use: the least over the
// process's cgroup and its ancestors, whose limits all apply, of cgroup v2's
// memory.max - memory.current ("0::/PATH" in /proc/self/cgroup) and cgroup
// v1's memory.limit_in_bytes - memory.usage_in_bytes ("N:memory:/PATH" or
// "N:...,memory,...:/PATH"); a container sees its own cgroup as the root,
// the host's path or not, so the walk up covers both. v1 writes "no limit"
// as a number near 2^63.
std::optional<MemoryLimit> cgroupLeft() {
  std::string v2Path = "/", v1Path = "/";
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    if (line.rfind("0::", 0) == 0) v2Path = line.substr(second + 1);
    std::istringstream controllers(line.substr(first + 1, second - first - 1));
    for (std::string name; std::getline(controllers, name, ',');) {
      if (name == "memory") v1Path = line.substr(second + 1);
    }
  }
  const std::string root = cgroupRoot();
  constexpr uint64_t kV1NoLimit = uint64_t{1} << 60;
  std::optional<MemoryLimit> tightest;
  const auto consider = [&](const std::string& folder, const char* limitFile, const char* usageFile,
                            const char* source) {
    const std::optional<uint64_t> max = readNumber(folder + "/" + limitFile);
    if (!max || *max >= kV1NoLimit) return;
    const uint64_t used = readNumber(folder + "/" + usageFile).value_or(0);
    const uint64_t left = *max > used ? *max - used : 0;
    if (!tightest || left < tightest->bytes) tightest = MemoryLimit{left, source};
  };
  for (const std::string& folder : selfAndAncestors(v2Path))
    consider(root + folder, "memory.max", "memory.current", "cgroup memory.max");
  for (const std::string& folder : selfAndAncestors(v1Path)) {
    consider(root + "/memory" + folder, "memory.limit_in_bytes", "memory.usage_in_bytes",
             "cgroup memory.limit_in_bytes");
  }
  return tightest;
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
  if (const std::optional<MemoryLimit> cgroup = cgroupLeft()) {
    if (!tightest || cgroup->bytes < tightest->bytes) tightest = cgroup;
  }
  return tightest;
}

std::optional<uint64_t> addressSpaceLeft() {
  return rlimitLeft(RLIMIT_AS, "VmSize:");
}

std::optional<std::string> addressSpaceShortfall(uint64_t bytes, const std::string& what) {
  const std::optional<uint64_t> left = addressSpaceLeft();
  if (!left || *left >= bytes) return std::nullopt;
  rlimit limit{};
  getrlimit(RLIMIT_AS, &limit);
  return what + " needs about " + std::to_string(bytes >> 20) +
         " MiB of address space, and this process's limit (ulimit -v " +
         std::to_string(limit.rlim_cur >> 10) + " kB) leaves " + std::to_string(*left >> 20) +
         " MiB: raise or remove the limit";
}

unsigned threadsThatFit(unsigned wanted) {
  const std::optional<uint64_t> left = addressSpaceLeft();
  if (!left) return wanted;
  rlimit stack{};
  constexpr uint64_t kDefaultStack = uint64_t{8} << 20;
  const uint64_t stackBytes =
      getrlimit(RLIMIT_STACK, &stack) == 0 && stack.rlim_cur != RLIM_INFINITY && stack.rlim_cur > 0
          ? stack.rlim_cur
          : kDefaultStack;
  constexpr uint64_t kReserve = uint64_t{64} << 20;
  const uint64_t spare = *left > kReserve ? (*left - kReserve) / 2 : 0;
  return static_cast<unsigned>(std::clamp<uint64_t>(spare / stackBytes, 1, std::max(wanted, 1u)));
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
