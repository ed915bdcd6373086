// Shared helpers of the DEM input tests: temporary folders, captured
// warnings, and checks on InputError messages.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "aperture/terrain/errors.h"
#include "aperture/terrain/heightfield.h"
#include "aperture/terrain/io/dem_options.h"
#include "aperture/tests/tools/run_tool.h"

namespace aal::test {

// Options whose warnings are collected instead of printed.
struct CapturedWarnings {
  std::vector<std::string> messages;
  DemLoadOptions options() {
    DemLoadOptions o;
    o.warn = [this](const std::string& m) { messages.push_back(m); };
    return o;
  }
  bool any(const std::string& part) const {
    for (const std::string& m : messages) {
      if (m.find(part) != std::string::npos) return true;
    }
    return false;
  }
};

// The message of the InputError `f` throws ("" and a test failure if none).
template <typename F>
std::string inputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected InputError, got another exception: " << e.what();
    return "";
  }
  ADD_FAILURE() << "expected InputError, nothing was thrown";
  return "";
}

// Checks that the message contains every part.
inline void expectMessage(const std::string& message, std::initializer_list<std::string> parts) {
  for (const std::string& part : parts) {
    EXPECT_NE(message.find(part), std::string::npos)
        << "message lacks '" << part << "': " << message;
  }
}

inline void writeBytes(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

inline bool allFinite(const Heightfield& f) {
  for (float v : f.z) {
    if (!std::isfinite(v)) return false;
  }
  return true;
}

}  // namespace aal::test
