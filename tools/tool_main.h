// The one place where a tool turns exceptions into messages and exit codes:
// 0 ok, 1 runtime failure, 2 bad usage or input.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <functional>
#include <iostream>
#include <new>
#include <sstream>
#include <string>
#include <system_error>

#include <CLI/CLI.hpp>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/interrupt.h"
#include "aperture/terrain/io/memory_budget.h"
#include "aperture/terrain/version.h"

namespace aal {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitBadInput = 2;

// Whether `text` is a number that is not finite ("nan", "inf", "1e999").
inline bool isNonFiniteNumber(const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double number = std::strtod(begin, &end);
  return end != begin && *end == '\0' && !std::isfinite(number);
}

// Throws InputError when the value of an option that takes one, or one of
// its comma-separated parts, is a number that is not finite. Before CLI11
// parses: its range checks let NaN through (every comparison with it is
// false) and answer "inf" with DBL_MAX printed in full, 309 digits. One
// check for every option of every tool.
inline void checkFiniteArguments(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    std::string name = argv[i], value;
    if (name.size() < 2 || name[0] != '-') continue;
    if (const size_t equals = name.find('='); equals != std::string::npos) {
      value = name.substr(equals + 1);
      name.resize(equals);
    } else if (i + 1 < argc) {
      value = argv[i + 1];
    }
    const CLI::Option* option = app.get_option_no_throw(name);
    if (option == nullptr || option->get_type_size() == 0) continue;
    std::stringstream parts(value);
    std::string part;
    while (std::getline(parts, part, ',')) {
      if (isNonFiniteNumber(part)) {
        throw InputError(name + " " + value +
                         ": every number must be finite (not NaN, infinite or beyond 1.8e308)");
      }
    }
  }
}

// Range checks against 0 that name the bound the user missed, without
// printing the type's limit ("0.000000 to 1.797...e308" in full is CLI11's).
inline CLI::Validator aboveZero(bool inclusive, const char* name) {
  return CLI::Validator(
      [inclusive](std::string& text) -> std::string {
        const char* begin = text.c_str();
        char* end = nullptr;
        const double number = std::strtod(begin, &end);
        if (end == begin || *end != '\0') return "'" + text + "' is not a number";
        if (inclusive ? number >= 0 : number > 0) return {};
        return std::string(inclusive ? "must be at least 0" : "must be greater than 0") + ", got " +
               text;
      },
      name);
}
inline const CLI::Validator kPositive = aboveZero(false, "POSITIVE");
inline const CLI::Validator kNonNegative = aboveZero(true, "NONNEGATIVE");

// After a parse error: a file whose name starts with '-' ("-x.tif") is read
// as an unknown option, and the error then says "dem is required". Names
// each such argument that is an existing file, and how to give it.
inline void hintDashedFileNames(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string text = argv[i];
    if (text == "--") break;  // what follows is positional already
    if (text.size() < 2 || text[0] != '-') continue;
    if (app.get_option_no_throw(text.substr(0, text.find('='))) != nullptr) continue;
    std::error_code error;
    if (!std::filesystem::exists(std::filesystem::symlink_status(text, error))) continue;
    std::cerr << "note: '" << text << "' is a file but was read as an option; give it as ./" << text
              << " or after -- (" << app.get_name() << " [OPTIONS] -- " << text << ")\n";
  }
}

// What a tool says when a thread could not start: one that could not start
// for lack of resources (EAGAIN) is memory or a process limit.
inline std::string threadFailureMessage(const std::system_error& e) {
  if (e.code() != std::errc::resource_unavailable_try_again) return e.what();
  return std::string("cannot start a thread (") + e.what() + "): " + outOfMemoryMessage("");
}

// Parses the command line with `app` and runs `body`; returns the exit code.
// `--version` prints "aal-bake 0.2.0 (abc1234)" (terrain/version.h) and exits 0.
inline int runToolBody(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  app.set_version_flag("--version", versionLine(app.get_name()),
                       "Print the tool's version and git revision, and exit");
  try {
    checkFiniteArguments(app, argc, argv);
  } catch (const InputError& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return kExitBadInput;
  }
  // Every tool: the first SIGINT, SIGTERM or SIGHUP stops it within a
  // second, its unfinished outputs removed (terrain/interrupt.h). Its
  // watchdog thread may not start under a tight ulimit -v.
  try {
    installInterruptHandler();
  } catch (const std::system_error& e) {
    std::cerr << app.get_name() << ": error: " << threadFailureMessage(e) << "\n";
    return kExitFailure;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help or the parse error
    if (code != 0) hintDashedFileNames(app, argc, argv);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    return body();
  } catch (const InputError& e) {
    std::cerr << app.get_name() << ": " << e.what() << "\n";
    return kExitBadInput;
  } catch (const Interrupted&) {
    std::cerr << app.get_name() << ": interrupted; unfinished outputs removed\n";
    return kExitFailure;
  } catch (const std::bad_alloc&) {
    // A limit (ulimit -v, a cgroup) or the machine: say memory, name the limit.
    std::cerr << app.get_name() << ": error: " << outOfMemoryMessage("") << "\n";
    return kExitFailure;
  } catch (const std::system_error& e) {
    std::cerr << app.get_name() << ": error: " << threadFailureMessage(e) << "\n";
    return kExitFailure;
  } catch (const std::exception& e) {
    // oneTBB says a worker it could not start with a runtime_error.
    if (std::string(e.what()).find("pthread_create") != std::string::npos) {
      std::cerr << app.get_name() << ": error: cannot start a thread (" << e.what()
                << "): " << outOfMemoryMessage("") << "\n";
    } else {
      std::cerr << app.get_name() << ": error: " << e.what() << "\n";
    }
    return kExitFailure;
  }
}

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define AAL_TOOL_EXITS_NORMALLY 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define AAL_TOOL_EXITS_NORMALLY 1
#endif
#endif

// Ends a tool whose work is done, every output closed and renamed in its
// scope: stdio and iostreams flushed, then _Exit, which skips the static
// destructors of GDAL's drivers, PROJ and the TBB and OpenEXR thread pools
// (about 10 ms of every run; docs/performance.md). Sanitizer builds return,
// so that LeakSanitizer still checks the heap at exit.
inline int endTool(int code) {
#ifdef AAL_TOOL_EXITS_NORMALLY
  return code;
#else
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  std::_Exit(code);
#endif
}

// Runs a tool's `body` after its command line is checked and parsed, and
// ends the process with its exit code (endTool).
inline int runTool(CLI::App& app, int argc, char** argv, const std::function<int()>& body) {
  return endTool(runToolBody(app, argc, argv, body));
}

}  // namespace aal
