// Runs one of the built tools (build/bin) as a child process and captures its
// exit code and output, for command-line contract tests.
#pragma once

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace aal::test {

struct ToolResult {
  int exitCode = -1;
  std::string out;  // stdout and stderr together
};

inline std::filesystem::path binDir() {
  return AAL_TEST_BIN_DIR;
}

// A path in single quotes for the shell command line of runTool (appended,
// not chained with +: GCC 12 reports a false -Wrestrict for that).
inline std::string quoted(const std::filesystem::path& path) {
  std::string q = "'";
  q += path.string();
  q += "'";
  return q;
}

// Runs a shell command line, capturing stdout and stderr together.
inline ToolResult runShell(const std::string& commandLine) {
  const std::string command = commandLine + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + command);
  ToolResult result;
  std::array<char, 4096> buffer;
  size_t n;
  while ((n = fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.out.append(buffer.data(), n);
  const int status = pclose(pipe);
  result.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

// `arguments` is passed to the shell as written: quote what needs quoting.
// `environment` ("NAME=value ...", or env options such as "-u NAME") is set
// for this run only.
inline ToolResult runTool(const std::string& tool, const std::string& arguments,
                          const std::string& environment = "") {
  return runShell((environment.empty() ? "" : "env " + environment + " ") +
                  (binDir() / tool).string() + " " + arguments);
}

// Bakes `dem` into the aperture map `map` with its directional horizons in
// `horizons` (aal-bake --horizons, by default 8 directions of 8 bits, which
// the tests' suns are placed for; quiet): the exit code.
inline int bakeWithHorizons(const std::filesystem::path& dem, const std::filesystem::path& map,
                            const std::filesystem::path& horizons, int directions = 8) {
  return runTool("aal-bake", quoted(dem) + " -o " + quoted(map) + " --horizons " +
                                 quoted(horizons) + " --horizon-directions " +
                                 std::to_string(directions) + " --horizon-bits 8 -q")
      .exitCode;
}

// aal-view in a private X server (xvfb-run; aal-view needs a display). The
// server number is searched from one derived from the pid, so tests run in
// parallel do not race for the same display. `environment` ("NAME=value
// ...") is set for the run. Under the sanitizer build scripts/test.sh
// preloads the ASan runtime and lavapipe (LD_PRELOAD): that is for aal-view
// alone, not for the X server and xauth that xvfb-run starts, which are not
// built for it and fail. The exit code is aal-view's own, kept in a file:
// xvfb-run replaces it with 5 when it cannot clean up its temporary folder
// afterwards (seen once in CI, after aal-view had exited 2).
inline ToolResult runViewer(const std::string& arguments, const std::string& environment = "") {
  static int runs = 0;
  const std::string server = std::to_string(100 + getpid() % 800);
  const std::filesystem::path status =
      std::filesystem::temp_directory_path() /
      ("aal-view-status-" + std::to_string(getpid()) + "-" + std::to_string(runs++));
  const char* preload = std::getenv("LD_PRELOAD");
  const std::string viewerEnv =
      preload && *preload ? "env LD_PRELOAD=" + quoted(std::filesystem::path(preload)) + " " : "";
  ToolResult r =
      runShell("env -u LD_PRELOAD AAL_VALIDATION=1 " + environment + " xvfb-run -a -n " + server +
               " -s '-screen 0 1280x720x24' sh -c '\"$@\"; echo $? > \"$0\"' " + quoted(status) +
               " " + viewerEnv + quoted(binDir() / "aal-view") + " " + arguments);
  std::ifstream code(status);
  if (int own = 0; code >> own) r.exitCode = own;
  code.close();
  std::filesystem::remove(status);
  return r;
}

// A fresh empty folder under the system temp folder, removed by the destructor.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "aal-test-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// Every file in `folder` with its bytes: what a refused run must leave as it was.
using FolderContents = std::map<std::string, std::string>;
inline FolderContents folderContents(const std::filesystem::path& folder) {
  FolderContents files;
  for (const std::filesystem::directory_entry& entry :
       std::filesystem::directory_iterator(folder)) {
    std::ifstream in(entry.path(), std::ios::binary);
    files[entry.path().filename().string()] =
        std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  return files;
}

// The names of the files added, removed or changed from `before` to `after`.
inline std::vector<std::string> changedFiles(const FolderContents& before,
                                             const FolderContents& after) {
  std::vector<std::string> changed;
  for (const auto& [name, bytes] : before) {
    const auto now = after.find(name);
    if (now == after.end() || now->second != bytes) changed.push_back(name);
  }
  for (const auto& [name, bytes] : after) {
    if (!before.count(name)) changed.push_back(name);
  }
  return changed;
}

// The PID of a process that has exited (and been reaped): no process has
// it now, unless the kernel reuses it at once.
inline pid_t deadPid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  int status = 0;
  ::waitpid(child, &status, 0);
  return child;
}

// Whether process `pid` catches `signal` (its bit in SigCgt of
// /proc/PID/status): a tool has installed its interrupt handler.
inline bool catchesSignal(pid_t pid, int signal) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("SigCgt:", 0) == 0) {
      return (std::stoull(line.substr(7), nullptr, 16) >> (signal - 1)) & 1u;
    }
  }
  return false;
}

// Runs tool `tool` with `arguments` and sends it SIGINT mid-run: once it
// catches the signal (however slowly it starts) and half a second later.
// Returns its exit code, or -1 when it did not exit by itself (a signal).
inline int interruptMidRun(const std::string& tool, const std::vector<std::string>& arguments) {
  const std::string path = (binDir() / tool).string();
  std::vector<char*> argv{const_cast<char*>(path.c_str())};
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, path.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return -2;
  for (int i = 0; i < 200 && !catchesSignal(pid, SIGINT); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ::kill(pid, SIGINT);
  int status = 0;
  if (::waitpid(pid, &status, 0) != pid || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

}  // namespace aal::test
