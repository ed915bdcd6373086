// What the tools' --progress tests share: a run with stdout and stderr
// apart, and a reader of --progress json's lines (docs/cli.md, "Progress for
// scripts").
#pragma once

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "aperture/tests/tools/run_tool.h"

namespace aal::test {

struct SplitRun {
  int exitCode = -1;
  std::string out, err;
};

inline std::string fileText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// `tool` with `arguments` (and `environment`, "NAME=value ..."), its stdout
// and stderr apart, through files in `dir`.
inline SplitRun runSplit(const std::string& tool, const TempDir& dir, const std::string& arguments,
                         const std::string& environment = "") {
  const std::filesystem::path out = dir.path() / "stdout.txt", err = dir.path() / "stderr.txt";
  // Appended, not chained with +: GCC 12 reports a false -Wrestrict.
  std::string command = "(";
  if (!environment.empty()) {
    command += "env ";
    command += environment;
    command += " ";
  }
  command += (binDir() / tool).string();
  command += " ";
  command += arguments;
  command += " >";
  command += quoted(out);
  command += " 2>";
  command += quoted(err);
  command += ")";
  const ToolResult r = runShell(command);
  return {r.exitCode, fileText(out), fileText(err)};
}

struct JsonLine {
  std::string stage;
  uint64_t done = 0, total = 0;
  double seconds = 0;
};

// One line of --progress json, read as JSON: an object of exactly the four
// members, in any order, strings and numbers as JSON writes them; false for
// anything else.
inline bool parseJsonLine(const std::string& line, JsonLine& parsed) {
  static const std::regex member(
      R"re(\s*"(stage|done|total|seconds)"\s*:\s*("[a-z ]*"|-?[0-9]+(\.[0-9]+)?([eE][-+]?[0-9]+)?)\s*)re");
  if (line.size() < 2 || line.front() != '{' || line.back() != '}') return false;
  std::stringstream body(line.substr(1, line.size() - 2));
  std::string part;
  int seen = 0;
  while (std::getline(body, part, ',')) {
    std::smatch m;
    if (!std::regex_match(part, m, member)) return false;
    const std::string name = m[1], value = m[2];
    if (name == "stage") {
      if (value.front() != '"') return false;
      parsed.stage = value.substr(1, value.size() - 2);
      seen |= 1;
    } else {
      if (value.front() == '"') return false;
      if (name == "seconds") {
        parsed.seconds = std::stod(value);
        seen |= 8;
      } else {
        if (value.find_first_of(".eE-") != std::string::npos) return false;  // counts
        (name == "done" ? parsed.done : parsed.total) = std::stoull(value);
        seen |= name == "done" ? 2 : 4;
      }
    }
  }
  return seen == 15;
}

inline std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::stringstream in(text);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
}

}  // namespace aal::test
