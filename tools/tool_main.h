// The one place where a tool turns exceptions into messages and exit codes:
// 0 ok, 1 runtime failure, 2 bad usage or input.
#pragma once

#include <cmath>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <sstream>
#include <string>

#include <CLI/CLI.hpp>

#include "errors.h"

namespace aal {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;

// Throws InputError when an option's value, or one of its comma-separated
// parts, is a number that is not finite ("nan", "inf", "1e999"): CLI11's
// range checks let NaN through, since every comparison with it is false.
// One check for every option of every tool.
inline void checkFiniteNumbers(const CLI::App& app) {
  for (const CLI::Option* option : app.get_options()) {
    if (!option->nonpositional() || option->count() == 0) continue;
    for (const std::string& value : option->results()) {
      std::stringstream parts(value);
      std::string part;
      while (std::getline(parts, part, ',')) {
        const char* begin = part.c_str();
        char* end = nullptr;
        const double number = std::strtod(begin, &end);
        if (end != begin && *end == '\0' && !std::isfinite(number)) {
          throw InputError(option->get_name() + " " + value +
                           ": every number must be finite (not NaN, infinite or beyond "
                           "1.8e308)");
        }
      }
    }
  }
}

// Parses the command line with `app` and runs `body`; returns the exit code.
inline int runTool(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help or the parse error
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    checkFiniteNumbers(app);
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
