#include "atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <string>
#include <system_error>

namespace aal {

namespace fs = std::filesystem;

void checkOutputWritable(const fs::path& path) {
  if (path.empty()) throw std::runtime_error("output path is empty");
  std::error_code error;
  if (fs::is_directory(path, error)) {
    throw std::runtime_error("output " + path.string() + " is a folder, not a file");
  }
  const fs::path folder = path.has_parent_path() ? path.parent_path() : fs::path(".");
  if (!fs::is_directory(folder, error)) {
    throw std::runtime_error("cannot write " + path.string() + ": folder " + folder.string() +
                             " does not exist");
  }
  if (::access(folder.c_str(), W_OK) != 0) {
    throw std::runtime_error("cannot write " + path.string() + ": folder " + folder.string() +
                             " is not writable");
  }
}

AtomicOutput::AtomicOutput(fs::path path) : final_(std::move(path)) {
  checkOutputWritable(final_);
  static std::atomic<unsigned> counter{0};
  const std::string unique = std::to_string(::getpid()) + "-" + std::to_string(counter++);
  // Built with += : GCC 12 reports a false -Wrestrict for chained + here.
  std::string name = ".";
  name += final_.stem().string();
  name += ".tmp-";
  name += unique;
  name += final_.extension().string();
  temporary_ = final_.parent_path() / name;
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) {
    std::error_code ignored;
    fs::remove(temporary_, ignored);
  }
}

void AtomicOutput::commit() {
  std::error_code error;
  fs::rename(temporary_, final_, error);
  if (error) {
    throw std::runtime_error("cannot move " + temporary_.string() + " to " + final_.string() +
                             ": " + error.message());
  }
  committed_ = true;
}

}  // namespace aal
