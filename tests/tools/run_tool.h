// Runs one of the built tools (build/bin) as a child process and captures its
// exit code and output, for command-line contract tests.
#pragma once

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <string>

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

}  // namespace aal::test
