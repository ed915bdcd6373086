// The one place where a tool turns exceptions into messages and exit codes:
// 0 ok, 1 runtime failure, 2 bad usage or input.
#pragma once

#include <exception>
#include <functional>
#include <iostream>

#include <CLI/CLI.hpp>

#include "errors.h"

namespace aal {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;

// Parses the command line with `app` and runs `body`; returns the exit code.
inline int runTool(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help or the parse error
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    return body();
  } catch (const InputError& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return kExitBadInput;
  } catch (const std::exception& e) {
    std::cerr << app.get_name() << ": error: " << e.what() << "\n";
    return kExitFailure;
  }
}

}  // namespace aal
