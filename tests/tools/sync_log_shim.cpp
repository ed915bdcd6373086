// A preloaded library (LD_PRELOAD) that logs every fsync and rename a
// process makes, in order, to the file named by AAL_SYNC_LOG: "fsync PATH"
// (the descriptor's path) and "rename FROM TO". durable_output_test.cpp
// reads the log to check that each output is flushed before it is renamed
// and its folder after. Plain system calls only: it runs inside the tools'
// own calls.
#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

namespace {

void logLine(const char* verb, const char* first, const char* second) {
  const char* path = getenv("AAL_SYNC_LOG");
  if (path == nullptr) return;
  char line[8192];
  const int n = second ? std::snprintf(line, sizeof line, "%s %s %s\n", verb, first, second)
                       : std::snprintf(line, sizeof line, "%s %s\n", verb, first);
  if (n <= 0) return;
  const int fd = open(path, O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return;
  ssize_t ignored = write(fd, line, size_t(n) < sizeof line ? size_t(n) : sizeof line - 1);
  (void)ignored;
  close(fd);
}

template <typename F>
F next(const char* name) {
  return reinterpret_cast<F>(dlsym(RTLD_NEXT, name));
}

}  // namespace

extern "C" int fsync(int fd) {
  char link[64], target[4096];
  std::snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, target, sizeof target - 1);
  target[n > 0 ? n : 0] = '\0';
  logLine("fsync", target, nullptr);
  return next<int (*)(int)>("fsync")(fd);
}

extern "C" int rename(const char* from, const char* to) {
  logLine("rename", from, to);
  return next<int (*)(const char*, const char*)>("rename")(from, to);
}
